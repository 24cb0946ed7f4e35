// What the face says, played in the page in step with the server's clock (Web Audio: to the sample).
// Shared by the studio's page and the screen's. Each status message from the server lists the
// sounds heard now ({key, at}: `at` is where the utterance starts on the clock of what is shown)
// and that clock's position `t`; the sound is fetched once as WAV and started from where the face is.
"use strict";
window.BaxterSound = function ({ token = null, isOn = () => true, needsTap = () => {} } = {}) {
  const playing = new Map(); // "key@at" -> {at, source, startedAt, duration, stopped}
  const buffers = new Map(); // sound key -> Promise of its decoded AudioBuffer
  // Seconds the sound may lag or stray from the face before it is moved into step: a sound that
  // arrives a moment late starts from its beginning rather than losing its first syllable.
  const SLACK = 0.15;
  const started = []; // what was started, for the tests: {key, at, offset, late}
  let audio = null; // the AudioContext, made once sound is first wanted

  // Browsers make no sound until the page has been used: `needsTap` is told when that is so.
  function context() {
    if (!audio) {
      audio = new AudioContext();
      audio.onstatechange = () => needsTap(audio.state !== "running");
    }
    if (audio.state === "suspended") audio.resume().catch(() => {});
    return audio;
  }

  function heardAt(status, receivedAt) {
    return status.t + (performance.now() - receivedAt) / 1000;
  }

  function decoded(key) {
    if (!buffers.has(key)) {
      if (buffers.size > 64) buffers.clear();
      const url = `/api/sound/${key}.wav${token ? "?token=" + encodeURIComponent(token) : ""}`;
      const promise = fetch(url)
        .then((r) => (r.ok ? r.arrayBuffer() : Promise.reject(new Error(`${r.status} for ${url}`))))
        .then((bytes) => audio.decodeAudioData(bytes));
      promise.catch(() => buffers.delete(key)); // asked again next time
      buffers.set(key, promise);
    }
    return buffers.get(key);
  }

  function sound(entry, buffer, offset) {
    const source = audio.createBufferSource();
    source.buffer = buffer;
    source.connect(audio.destination);
    source.start(0, offset);
    source.onended = () => source === entry.source && (entry.source = null);
    entry.source = source;
    entry.buffer = buffer;
    entry.startedAt = audio.currentTime - offset;
    entry.duration = buffer.duration;
  }

  function stopSound(id) {
    const entry = playing.get(id);
    entry.stopped = true;
    if (entry.source) entry.source.stop();
    playing.delete(id);
  }

  function startSound(id, u, status, receivedAt) {
    context();
    const entry = { at: u.at, source: null, startedAt: 0, duration: 0, stopped: false };
    playing.set(id, entry);
    decoded(u.key).then(
      (buffer) => {
        if (entry.stopped) return;
        if (audio.state !== "running") {
          // Asked again with the next status, once the page has been used.
          playing.delete(id);
          needsTap(true);
          return;
        }
        const late = heardAt(status, receivedAt) - u.at;
        if (late >= buffer.duration) return;
        const offset = late > SLACK ? late : 0;
        sound(entry, buffer, offset);
        started.push({ key: u.key, at: u.at, offset, late });
        needsTap(false);
      },
      () => playing.delete(id),
    );
  }

  // A status message: start what is heard now, keep what plays in step, stop what is no longer heard.
  function play(status, receivedAt) {
    const wanted = new Set();
    for (const u of isOn() ? status.sounds || [] : []) {
      const id = `${u.key}@${u.at}`;
      wanted.add(id);
      const entry = playing.get(id);
      if (!entry) {
        startSound(id, u, status, receivedAt);
      } else if (entry.source) {
        const due = heardAt(status, receivedAt) - u.at;
        if (Math.abs(audio.currentTime - entry.startedAt - due) > SLACK + 0.05 && due < entry.duration) {
          const old = entry.source;
          sound(entry, entry.buffer, Math.max(0, due)); // sought or slipped: back in step
          old.stop();
        }
      }
    }
    for (const [id, entry] of playing) {
      if (wanted.has(id)) continue;
      // One that ends a moment before the face says so finishes; paused, sought away or off, it stops.
      const left = entry.duration - (audio.currentTime - entry.startedAt);
      if (isOn() && status.playing && entry.source && left < 0.25) continue;
      stopSound(id);
    }
  }

  // Fetch sounds before they are heard (once there is a context to decode them in).
  function prefetch(keys) {
    if (audio && isOn()) for (const key of keys || []) decoded(key);
  }

  return {
    play,
    prefetch,
    // The page was used (or is about to be): the context is made then, ready before it is needed.
    wake(keys) {
      if (!isOn()) return;
      context();
      prefetch(keys);
    },
    silence: () => play({ sounds: [], playing: false }, performance.now()),
    sounds: () =>
      [...playing.values()].map((e) => ({ at: e.at, t: audio.currentTime - e.startedAt, paused: !e.source })),
    state: () => (audio ? audio.state : "none"),
    started,
  };
};
