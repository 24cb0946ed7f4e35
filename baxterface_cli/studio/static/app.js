// The studio's page: the editor, the preview and its transport, the button panel and the session.
// Everything it does goes through the HTTP API and one WebSocket; the face is drawn by the server.
"use strict";
(function () {
  const $ = (id) => document.getElementById(id);
  const token = new URLSearchParams(location.search).get("token");
  const headers = token ? { "X-Baxterface-Token": token } : {};

  async function api(method, path, body) {
    const init = { method, headers: { ...headers } };
    if (body !== undefined) {
      init.body = typeof body === "string" ? body : JSON.stringify(body);
      init.headers["Content-Type"] = typeof body === "string" ? "text/plain; charset=utf-8" : "application/json";
    }
    const response = await fetch(path, init);
    let data = null;
    try {
      data = await response.json();
    } catch (e) {
      data = { error: `${response.status} ${response.statusText}` };
    }
    return { ok: response.ok, status: response.status, data };
  }

  let editor = null;
  let saved = "";
  let duration = 0;
  let spans = [];
  let dragging = false;
  let scriptSounds = []; // the keys of what the script says, fetched before they are heard
  window.__frames = 0;

  // -- the editor

  function showDiagnostics(list) {
    const ul = $("diagnostics");
    ul.replaceChildren();
    for (const d of list) {
      const li = document.createElement("li");
      li.className = `diagnostic ${d.severity}`;
      li.textContent = d.line ? `${d.line}:${d.column}: ${d.severity}: ${d.message}` : `${d.severity}: ${d.message}`;
      li.onclick = () => {
        if (!d.line) return;
        const line = editor.view.state.doc.line(Math.min(d.line, editor.view.state.doc.lines));
        editor.view.dispatch({ selection: { anchor: Math.min(line.to, line.from + d.column - 1) }, scrollIntoView: true });
        editor.focus();
      };
      ul.appendChild(li);
    }
    window.__lintShownAt = performance.now();
    window.__lintVersion = editor ? editor.version : 0;
  }

  async function lint(text, version) {
    const { ok, data } = await api("POST", "/api/check", text);
    if (!editor || version !== editor.version) return null; // stale: a newer one is coming
    const list = ok && Array.isArray(data) ? data : [{ line: 0, column: 0, severity: "error", message: data.error || "check failed" }];
    showDiagnostics(list);
    return list;
  }

  function markSaved() {
    const clean = editor.getText() === saved;
    $("saved").textContent = clean ? "saved" : "unsaved";
    $("saved").className = clean ? "marker" : "marker unsaved";
  }

  let scriptTimer = null;
  function edited(text) {
    markSaved();
    clearTimeout(scriptTimer);
    scriptTimer = setTimeout(async () => {
      const { ok, data } = await api("POST", "/api/script", text);
      if (ok) showTimeline(data.timeline);
    }, 150);
  }

  // The version of the file the editor's text is based on: a save over a file that changed on disk
  // since then is answered 409, and the page asks before it overwrites that change.
  let version = 0;

  async function save() {
    const text = editor.getText();
    let { ok, status, data } = await api("POST", `/api/save?base=${version}`, text);
    if (status === 409) {
      if (!window.confirm(`${data.error}. Overwrite it with the editor's text?`)) {
        $("notice").textContent = `not saved: ${data.error}`;
        return;
      }
      ({ ok, status, data } = await api("POST", "/api/save?force=1", text));
    }
    if (ok) {
      saved = text;
      version = data.version;
      $("notice").textContent = "";
      markSaved();
    } else {
      $("notice").textContent = data.error || "could not save";
    }
  }

  function diskChanged(message) {
    if (editor.getText() === saved) {
      saved = message.text;
      version = message.version;
      editor.setText(message.text);
      markSaved();
      return;
    }
    saved = message.text; // the editor's own text stays, and still says it is based on the old version
    const notice = $("notice");
    notice.replaceChildren(`${message.name} changed on disk `);
    const reload = document.createElement("button");
    reload.textContent = "Reload";
    reload.onclick = () => {
      editor.setText(message.text);
      version = message.version;
      notice.replaceChildren();
      markSaved();
    };
    notice.appendChild(reload);
    markSaved();
  }

  // -- the preview

  function showTimeline(timeline) {
    duration = timeline.duration;
    spans = timeline.spans;
    scriptSounds = timeline.sounds;
    showListens(timeline.listens || [], timeline.fired || 0);
    voice.prefetch(scriptSounds);
    $("scrub").max = String(duration || 1);
    const ol = $("timeline");
    ol.replaceChildren();
    for (const s of spans) {
      const li = document.createElement("li");
      const when = s.end > s.start ? `${s.start.toFixed(2)}–${s.end.toFixed(2)}` : s.start.toFixed(2);
      li.textContent = `${when} s  line ${s.line}  ${s.text}`;
      li.onclick = () => api("POST", "/api/transport", { action: "seek", t: s.start });
      ol.appendChild(li);
    }
    showLanes(timeline.lanes || {});
  }

  // The run's log under the preview (studio/lanes.py): its events, handlers' runs, states and
  // speech as bars along the script's length; a click anywhere on a lane puts the preview there.
  const LANES = ["events", "handlers", "states", "said"];
  function showLanes(lanes) {
    const box = $("lanes");
    box.replaceChildren();
    const length = duration || 1;
    for (const name of LANES) {
      const row = document.createElement("div");
      row.className = "lane";
      row.dataset.lane = name;
      const label = document.createElement("span");
      label.className = "lane-name";
      label.textContent = name;
      const track = document.createElement("div");
      track.className = "track";
      for (const bar of lanes[name] || []) {
        const b = document.createElement("span");
        b.className = "bar";
        b.style.left = `${(100 * bar.start) / length}%`;
        b.style.width = `${(100 * (bar.end - bar.start)) / length}%`;
        b.title = `${bar.start.toFixed(2)}–${bar.end.toFixed(2)} s  ${bar.text}`;
        b.textContent = bar.text;
        track.appendChild(b);
      }
      track.onclick = (e) => {
        const box = track.getBoundingClientRect();
        const t = (Math.min(Math.max(e.clientX - box.left, 0), box.width) / box.width) * length;
        api("POST", "/api/transport", { action: "seek", t: Math.round(t * 1000) / 1000 });
      };
      row.append(label, track);
      box.appendChild(row);
    }
  }

  function showStatus(s) {
    $("play").textContent = s.mode === "script" && s.playing ? "Pause" : "Play";
    $("mode").textContent = s.mode === "session" ? "live session" : "script";
    $("time").textContent = `${s.t.toFixed(2)} / ${s.duration.toFixed(2)} s`;
    $("loop").checked = s.loop;
    // The slider follows what is shown: the script along its length, or the live session, which
    // grows with the clock and is watched rather than sought (Play goes back to the script).
    const scrub = $("scrub");
    scrub.max = String(s.duration || 1);
    scrub.disabled = s.mode === "session";
    if (!dragging || s.mode === "session") scrub.value = String(s.t);
    $("lanes").style.setProperty("--at", `${(100 * s.t) / (duration || 1)}%`);
    $("lanes").classList.toggle("away", s.mode !== "script");
    if (s.mode === "script") {
      [...$("timeline").children].forEach((li, i) => {
        const span = spans[i];
        li.classList.toggle("now", !!span && span.start <= s.t && s.t < Math.max(span.end, span.start + 0.05));
      });
    }
    const r = s.robot || {};
    const seen = r.seen === true ? ", seen" : r.seen === false ? ", not seen" : "";
    const rows = [
      ["head", typeof r.head_pan_deg === "number" ? `${r.head_pan_deg.toFixed(1)}°` : "—"],
      ["robot", r.enabled == null ? "unknown" : r.enabled ? "enabled" : "disabled"],
      ["following", r.following ? r.following + (r.follow_dynamic ? " (dynamic)" : "") + seen : "nothing"],
      ["nodding", r.nodding ? "yes" : "no"],
      ["saying", r.saying ? `“${r.saying}”` : "—"],
    ];
    if (s.note) rows.push(["note", s.note]);
    if (s.face) pad.follow(s.face.mood);
    const panel = $("robot");
    panel.replaceChildren();
    for (const [label, value] of rows) {
      const div = document.createElement("div");
      const span = document.createElement("span");
      span.className = "label";
      span.textContent = label;
      div.append(span, value);
      panel.appendChild(div);
    }
  }

  // -- the sound: what the preview says, played here in step with its clock (sound.js)

  const HEAR = "click the page to hear the speech";
  function soundOn() {
    return $("sound").checked;
  }
  const voice = window.BaxterSound({
    token,
    isOn: soundOn,
    needsTap(needed) {
      if (needed) $("notice").textContent = HEAR;
      else if ($("notice").textContent === HEAR) $("notice").textContent = "";
    },
  });
  window.__sounds = voice.started; // what was started, for the tests: {key, at, offset}

  // The first use of the page may start sound: the context is made then, ready before it is needed.
  const wake = () => voice.wake(scriptSounds);
  document.addEventListener("pointerdown", wake);
  document.addEventListener("keydown", wake);

  let frameUrl = null;
  const preview = $("preview");
  // The size of the last frame shown: while the next one loads, the image may say none, and a tap
  // then must still count.
  let frameSize = null;
  preview.onload = () => {
    frameSize = [preview.naturalWidth, preview.naturalHeight];
    window.__frames += 1;
    window.__lastFrameAt = performance.now();
  };

  function connect() {
    const scheme = location.protocol === "https:" ? "wss" : "ws";
    const ws = new WebSocket(`${scheme}://${location.host}/api/live${token ? "?token=" + encodeURIComponent(token) : ""}`);
    ws.binaryType = "blob";
    ws.onmessage = (event) => {
      if (typeof event.data !== "string") {
        const url = URL.createObjectURL(event.data);
        preview.src = url;
        if (frameUrl) URL.revokeObjectURL(frameUrl);
        frameUrl = url;
        return;
      }
      const message = JSON.parse(event.data);
      if (message.kind === "status") {
        showStatus(message);
        voice.play(message, performance.now());
      }
      else if (message.kind === "disk") diskChanged(message);
      else if (message.kind === "timeline") showTimeline(message.timeline);
      else if (message.kind === "session") showSession(message.session);
      else if (message.kind === "buttons") showButtons(message.buttons);
      else if (message.kind === "notice") $("notice").textContent = message.message;
    };
    ws.onclose = () => setTimeout(connect, 1000);
  }

  // -- the live session

  function showSession(session) {
    const ol = $("session");
    ol.replaceChildren();
    for (const p of session.presses) {
      const li = document.createElement("li");
      li.textContent = `${p.at.toFixed(3).padStart(8)} s  ${p.command.replace(/\n/g, "; ")}`;
      ol.appendChild(li);
    }
    ol.scrollTop = ol.scrollHeight;
  }

  async function press(command) {
    const { ok, data } = await api("POST", "/api/command", command);
    $("command-error").textContent = ok
      ? ""
      : (data.diagnostics || [{ message: data.error }]).map((d) => (d.line ? `${d.line}:${d.column}: ` : "") + d.message).join("\n");
    if (ok) showSession(data.session);
    if (ok && data.reacting) showReacting(data);
    return ok;
  }

  // A press that reacts went to the script's run: the handlers it installed, or the signals it fired.
  function showReacting(data) {
    const said = data.fired
      ? data.fired.map((f) => `${f.event} at ${f.at} s: ran ${f.runs}, dropped ${f.dropped}, queued ${f.queued}`)
      : [`installed: ${data.installed.join(", ")}`, ...data.replaced];
    $("event-result").textContent = said.join("; ");
    $("event-result").classList.add("fired");
  }

  // A tap on the preview raises `touch` for the script's handlers, as on the screen's page: the page
  // says where, as fractions of the frame it shows (letterboxed if the box is not the frame's
  // shape); the server finds what is drawn there.
  preview.addEventListener("pointerdown", async (event) => {
    if (!frameSize) return;
    const where = window.baxterfaceTapAt(preview, frameSize[0], frameSize[1], event);
    const { ok, data } = await api("POST", "/api/touch", where);
    $("event-result").textContent = ok
      ? `${data.event} at ${data.at} s: ran ${data.runs}, dropped ${data.dropped}, queued ${data.queued}`
      : (data.diagnostics || [{ message: data.error }]).map((d) => d.message).join("\n");
    $("event-result").classList.toggle("fired", ok);
  });

  // The events bar: a button for each event the script's handlers wait for, and a line for any.
  function showListens(listens, fired) {
    const bar = $("event-buttons");
    bar.replaceChildren();
    for (const line of listens) {
      const button = document.createElement("button");
      button.type = "button";
      button.className = "press";
      button.textContent = line;
      button.onclick = () => fire(line);
      bar.appendChild(button);
    }
    bar.title = `${fired} event${fired === 1 ? "" : "s"} fired in this session`;
  }

  async function fire(line) {
    const { ok, data } = await api("POST", "/api/event", line);
    const said = ok
      ? `${data.event} at ${data.at} s: ran ${data.runs}, dropped ${data.dropped}, queued ${data.queued}`
      : (data.diagnostics || [{ message: data.error }]).map((d) => (d.line ? `${d.line}:${d.column}: ` : "") + d.message).join("\n");
    $("event-result").textContent = said;
    $("event-result").classList.toggle("fired", ok);
    return ok;
  }

  let shortcuts = new Map();
  function showButtons(buttons) {
    const panel = $("buttons");
    panel.replaceChildren();
    shortcuts = new Map();
    const groups = new Map();
    for (const b of buttons) {
      if (!groups.has(b.group)) {
        const div = document.createElement("div");
        div.className = "group";
        const name = document.createElement("span");
        name.textContent = b.group;
        div.appendChild(name);
        panel.appendChild(div);
        groups.set(b.group, div);
      }
      const button = document.createElement("button");
      button.className = "press";
      button.title = b.command;
      button.textContent = b.label;
      if (b.key) {
        const kbd = document.createElement("kbd");
        kbd.textContent = b.key.replace(/^Arrow/, "");
        button.appendChild(kbd);
        shortcuts.set(b.key, button);
      }
      button.onclick = () => {
        button.classList.add("flash");
        setTimeout(() => button.classList.remove("flash"), 150);
        press(b.command);
      };
      groups.get(b.group).appendChild(button);
    }
  }

  // -- the mood pad and the intensity slider: presses too, sent as they move

  // A moving control sends one line at a time, at most every LIVE_EVERY ms, the newest position
  // winning; the last one always goes, so the face ends where the control was let go. A line the
  // same as the one before is sent again only when asked (`again`: a new click or key press).
  const LIVE_EVERY = 100;
  const LIVE_IN = "0.2s";

  // A number as the line writes it: within its range, to 2 decimals, no "-0".
  function rounded(value, low, high) {
    const v = Math.round(Math.min(high, Math.max(low, Number.isFinite(value) ? value : 0)) * 100) / 100;
    return v === 0 ? 0 : v;
  }
  const moodLine = (valence, arousal) => `mood ${rounded(valence, -1, 1)} ${rounded(arousal, -1, 1)} in ${LIVE_IN}`;
  const intensityLine = (emotion, intensity) => `${emotion} ${rounded(intensity, 0, 1)} in ${LIVE_IN}`;

  function liveSender() {
    let wanted = null;
    let sent = null;
    let busy = false;
    let last = -Infinity; // when the last line went
    let timer = null;
    function go() {
      timer = null;
      if (busy || wanted === null || wanted === sent) return;
      const wait = last + LIVE_EVERY - performance.now();
      if (wait > 0) {
        timer = setTimeout(go, wait);
        return;
      }
      const line = wanted;
      busy = true;
      sent = line;
      last = performance.now();
      press(line)
        .catch(() => false)
        .finally(() => {
          busy = false;
          go();
        });
    }
    return {
      send(line, again = false) {
        wanted = line;
        if (again) sent = null;
        if (!timer) go();
      },
      // Nothing on its way, nor lately sent: the control may follow the face again.
      quiet: () => !busy && timer === null && performance.now() - last > 600,
    };
  }

  const pad = { set: () => {}, follow: () => {} };

  function showFeelings(feelings) {
    const area = $("mood-pad");
    const dot = $("mood-dot");
    const sender = liveSender();
    let valence = 0;
    let arousal = 0;
    let held = null; // the pointer dragging the dot

    for (const { emotion, degrees } of feelings.mood_circle) {
      const tick = document.createElement("span");
      const angle = (degrees * Math.PI) / 180;
      tick.className = "tick";
      tick.title = `${emotion} (${degrees}°)`;
      tick.style.left = `${50 + 46 * Math.cos(angle)}%`;
      tick.style.top = `${50 - 46 * Math.sin(angle)}%`;
      area.insertBefore(tick, dot);
    }

    function show() {
      dot.style.left = `${(valence + 1) * 50}%`;
      dot.style.top = `${(1 - arousal) * 50}%`;
      $("mood-value").textContent = `${valence} ${arousal}`;
      area.setAttribute("aria-valuenow", String(valence));
      area.setAttribute("aria-valuetext", `valence ${valence}, arousal ${arousal}`);
    }
    pad.set = (v, a, again = false) => {
      valence = rounded(v, -1, 1);
      arousal = rounded(a, -1, 1);
      show();
      sender.send(moodLine(valence, arousal), again);
    };
    // The face's own mood (a `mood` pressed or played elsewhere), while the pad is left alone.
    pad.follow = (mood) => {
      if (held !== null || !sender.quiet() || !Array.isArray(mood)) return;
      valence = rounded(mood[0], -1, 1);
      arousal = rounded(mood[1], -1, 1);
      show();
    };
    const at = (event) => {
      const r = area.getBoundingClientRect();
      return [((event.clientX - r.left) / r.width) * 2 - 1, 1 - ((event.clientY - r.top) / r.height) * 2];
    };
    area.addEventListener("pointerdown", (event) => {
      if (event.button !== 0) return;
      event.preventDefault();
      area.focus();
      held = event.pointerId;
      area.setPointerCapture(held);
      area.classList.add("dragging");
      pad.set(...at(event), true);
    });
    area.addEventListener("pointermove", (event) => {
      if (event.pointerId === held) pad.set(...at(event));
    });
    const release = (event) => {
      if (event.pointerId !== held) return;
      held = null;
      area.classList.remove("dragging");
      if (event.type === "pointerup") pad.set(...at(event));
    };
    area.addEventListener("pointerup", release);
    area.addEventListener("pointercancel", release);
    area.addEventListener("keydown", (event) => {
      const step = event.shiftKey ? 0.01 : 0.1;
      const moves = {
        ArrowLeft: [-step, 0],
        ArrowRight: [step, 0],
        ArrowUp: [0, step],
        ArrowDown: [0, -step],
      };
      const again = !event.repeat;
      if (event.key === "Home") pad.set(0, 0, again);
      else if (moves[event.key]) pad.set(valence + moves[event.key][0], arousal + moves[event.key][1], again);
      else return;
      event.preventDefault();
    });

    const emotion = $("intensity-emotion");
    const slider = $("intensity");
    const intensitySender = liveSender();
    for (const word of feelings.emotions) {
      const option = document.createElement("option");
      option.value = word;
      option.textContent = word.replace(/_/g, " ");
      emotion.appendChild(option);
    }
    const perform = () => {
      $("intensity-value").textContent = String(rounded(Number(slider.value), 0, 1));
      intensitySender.send(intensityLine(emotion.value, Number(slider.value)));
    };
    slider.addEventListener("input", perform);
    slider.addEventListener("change", perform);
    emotion.addEventListener("change", perform);
    $("intensity-value").textContent = String(rounded(Number(slider.value), 0, 1));
  }

  // Focus in the editor or a field that takes text: keys are for it, not shortcuts.
  // (A checkbox, the preview's slider or a button keeps the shortcuts working; the mood pad and
  // the intensity slider keep only the keys that move them.)
  const NOT_TEXT = ["checkbox", "radio", "range", "button", "submit", "reset", "color", "file"];
  const MOVING_KEYS = ["ArrowLeft", "ArrowRight", "ArrowUp", "ArrowDown", "Home", "End", "PageUp", "PageDown"];
  function typing(target) {
    if (!target || !target.closest) return false;
    if (target.closest(".cm-editor") || target.isContentEditable) return true;
    if (target.tagName === "TEXTAREA" || target.tagName === "SELECT") return true;
    return target.tagName === "INPUT" && !NOT_TEXT.includes(target.type);
  }

  document.addEventListener("keydown", (event) => {
    if ((event.ctrlKey || event.metaKey) && event.key.toLowerCase() === "s") {
      event.preventDefault();
      save();
      return;
    }
    if (event.ctrlKey || event.metaKey || event.altKey || typing(event.target)) return;
    // The mood pad and the intensity slider move with the arrows (and Home, End, Page Up, Page Down).
    if (event.target.closest && event.target.closest(".owns-arrows") && MOVING_KEYS.includes(event.key)) return;
    if (event.key === " ") {
      event.preventDefault();
      $("play").click();
      return;
    }
    const button = shortcuts.get(event.key);
    if (button) {
      event.preventDefault();
      button.click();
    }
  });

  // -- wiring

  async function start() {
    const { data: state } = await api("GET", "/api/state");
    $("name").textContent = state.script.name;
    saved = state.script.saved ? state.script.text : "";
    version = state.script.version;
    editor = window.BaxterEditor.create($("editor"), {
      doc: state.script.text,
      vocabulary: state.vocabulary,
      lint,
      onChange: edited,
    });
    editor.relint(); // its first lint ran before `editor` was there to take the answer
    markSaved();
    showTimeline(state.timeline);
    showButtons(state.buttons);
    showFeelings(state.feelings);
    showSession(state.session);
    $("robot-switch").checked = state.robot_link.on;
    $("robot-status").textContent = state.robot_link.status;
    $("save").onclick = save;
    $("play").onclick = () => api("POST", "/api/transport", { action: $("play").textContent === "Play" ? "play" : "pause" });
    $("loop").onchange = () => api("POST", "/api/transport", { action: "loop", on: $("loop").checked });
    $("sound").checked = localStorage.getItem("baxterface.sound") !== "off";
    $("sound").onchange = () => {
      localStorage.setItem("baxterface.sound", soundOn() ? "on" : "off");
      if (!soundOn()) voice.silence();
    };
    const scrub = $("scrub");
    scrub.onpointerdown = () => (dragging = true);
    window.addEventListener("pointerup", () => (dragging = false));
    window.addEventListener("pointercancel", () => (dragging = false));
    scrub.onchange = () => (dragging = false);
    scrub.oninput = () => api("POST", "/api/transport", { action: "seek", t: Number(scrub.value) });
    $("command-form").onsubmit = async (event) => {
      event.preventDefault();
      if (await press($("command").value)) $("command").value = "";
    };
    $("robot-switch").onchange = async () => {
      const { data } = await api("POST", "/api/robot", { on: $("robot-switch").checked });
      $("robot-switch").checked = !!data.on;
      $("robot-status").textContent = data.status || data.error || "";
    };
    $("export").onclick = async () => {
      const { ok, data } = await api("POST", "/api/session/export");
      const result = $("export-result");
      result.replaceChildren();
      if (!ok) {
        result.textContent = data.error;
        return;
      }
      const link = document.createElement("a");
      link.href = URL.createObjectURL(new Blob([data.text], { type: "text/plain" }));
      link.download = data.path;
      link.textContent = "download";
      result.append(`wrote ${data.path} beside the script `, link);
      if (data.events_path) {
        const events = document.createElement("a");
        events.href = URL.createObjectURL(new Blob([data.events_text], { type: "text/plain" }));
        events.download = data.events_path;
        events.textContent = "events";
        result.append(`; the script and its events as ${data.script_path} and ${data.events_path} `, events);
      }
    };
    $("events-bar").onsubmit = async (event) => {
      event.preventDefault();
      if (await fire($("event-line").value)) $("event-line").value = "";
    };
    $("clear").onclick = async () => {
      const { data } = await api("POST", "/api/session/clear");
      showSession(data);
    };
    window.studio = { editor, press, api, sounds: voice.sounds, moodLine, intensityLine };
    connect();
  }

  start();
})();
