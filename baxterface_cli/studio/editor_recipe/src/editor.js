// The studio's editor: CodeMirror 6 with the face language coloured and the
// server's diagnostics (the very ones `baxterface check` prints) underlined.
// The word lists come from the server, out of the tables the parser uses.
import { basicSetup } from "codemirror";
import { EditorView } from "@codemirror/view";
import { EditorState } from "@codemirror/state";
import { StreamLanguage, HighlightStyle, syntaxHighlighting } from "@codemirror/language";
import { linter, lintGutter, forceLinting } from "@codemirror/lint";
import { tags } from "@lezer/highlight";

const LEGACY = /^(dynamic_look|look|wobble|skin)(_[-+]?(\d+(\.\d*)?|\.\d+))+/i;
const NUMBER = /^[-+]?(\d+(\.\d*)?|\.\d+)([a-z%][a-z0-9_%]*)?/i;
const WORD = /^[a-z_][a-z0-9_]*(-[a-z0-9_]+)*/i;

function faceLanguage(vocabulary) {
  const lower = (list) => new Set((list || []).map((w) => w.toLowerCase()));
  const keywords = lower(vocabulary.keywords);
  const words = lower([...(vocabulary.words || []), ...(vocabulary.emotions || [])]);
  const names = lower([
    ...(vocabulary.easings || []),
    ...(vocabulary.mouths || []),
    ...(vocabulary.brows || []),
    ...(vocabulary.directions || []),
  ]);
  return StreamLanguage.define({
    name: "face",
    token(stream) {
      if (stream.eatSpace()) return null;
      if (stream.peek() === "#") {
        stream.skipToEnd();
        return "comment";
      }
      if (stream.peek() === '"') {
        stream.next();
        let escaped = false;
        while (!stream.eol()) {
          const c = stream.next();
          if (c === '"' && !escaped) break;
          escaped = !escaped && c === "\\";
        }
        return "string";
      }
      if (stream.match(LEGACY)) return "atom";
      if (stream.match(NUMBER)) return "number";
      const word = stream.match(WORD);
      if (word) {
        const w = word[0].toLowerCase();
        if (keywords.has(w)) return "keyword";
        if (words.has(w)) return "atom";
        if (names.has(w)) return "variableName.special";
        return "variableName";
      }
      const c = stream.next();
      if (c === "{" || c === "}") return "brace";
      if (c === ";") return "punctuation";
      return null;
    },
    languageData: { commentTokens: { line: "#" } },
  });
}

const style = HighlightStyle.define([
  { tag: tags.keyword, color: "#7a3e9d", fontWeight: "bold" },
  { tag: tags.atom, color: "#005cc5" },
  { tag: tags.number, color: "#b35900" },
  { tag: tags.string, color: "#22863a" },
  { tag: tags.comment, color: "#8a8f98", fontStyle: "italic" },
  { tag: tags.special(tags.variableName), color: "#0e7c86" },
  { tag: tags.brace, color: "#444" },
]);

// The end of the word at `from`, so an underline covers what is wrong and no more.
function wordEnd(doc, from) {
  const line = doc.lineAt(from);
  const rest = line.text.slice(from - line.from);
  const m = rest.match(/^("(\\.|[^"\\])*"?|[^\s;{}#]+)/);
  return Math.min(line.to, from + Math.max(1, m ? m[0].length : 1));
}

function toDiagnostics(doc, list) {
  return list.map((d) => {
    let from = 0;
    if (d.line >= 1 && d.line <= doc.lines) {
      const line = doc.line(d.line);
      from = Math.min(line.to, line.from + Math.max(0, d.column - 1));
    }
    const to = doc.length ? Math.max(from + 1, wordEnd(doc, from)) : from;
    return {
      from: Math.min(from, doc.length),
      to: Math.min(to, doc.length),
      severity: d.severity === "warning" ? "warning" : "error",
      message: d.message,
    };
  });
}

function create(parent, options) {
  const lint = options.lint || (() => Promise.resolve([]));
  let version = 0; // one more each change, so a slow answer for old text is dropped
  const source = async (view) => {
    const asked = version;
    const text = view.state.doc.toString();
    const list = await lint(text, asked);
    if (asked !== version || !Array.isArray(list)) return [];
    return toDiagnostics(view.state.doc, list);
  };
  const view = new EditorView({
    parent,
    state: EditorState.create({
      doc: options.doc || "",
      extensions: [
        basicSetup,
        faceLanguage(options.vocabulary || {}),
        syntaxHighlighting(style),
        linter(source, { delay: 25 }),
        lintGutter(),
        EditorView.updateListener.of((update) => {
          if (update.docChanged) {
            version += 1;
            if (options.onChange) options.onChange(update.state.doc.toString(), version);
          }
        }),
      ],
    }),
  });
  return {
    view,
    get version() {
      return version;
    },
    getText: () => view.state.doc.toString(),
    setText(text) {
      view.dispatch({ changes: { from: 0, to: view.state.doc.length, insert: text } });
    },
    relint: () => forceLinting(view),
    focus: () => view.focus(),
  };
}

window.BaxterEditor = { create };
