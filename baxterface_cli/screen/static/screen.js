// The screen's page: the face alone, as frames pushed by the server over one WebSocket, and what it
// says played here (sound.js). It keeps the screen awake where the browser can (the Screen Wake Lock
// API), and comes back by itself when the server restarts or the network drops.
"use strict";
(function () {
  const token = new URLSearchParams(location.search).get("token");
  const face = document.getElementById("face");
  const tap = document.getElementById("tap");
  const offline = document.getElementById("offline");
  const RETRY = [250, 500, 1000, 2000]; // ms between tries to reconnect, the last one repeated
  const SILENT = 5000; // ms without a word from the server (it speaks every second): the link is dead
  const OFFLINE_AFTER = 2000; // ms disconnected before the page says so

  // What the page has done, for the tests and the benchmark.
  const shown = (window.screenFace = {
    frames: 0, // shown
    lastFrameAt: 0,
    received: 0, // frames received (a page that falls behind shows only the newest)
    bytes: 0, // frames and messages received
    frameBytes: 0, // of which frames
    connected: false,
    connections: 0,
    touches: [], // what each tap raised, as the server answered ("touch left eye"), newest last
    awake: "not asked",
    sound: () => voice.state(),
    sounds: () => voice.sounds(),
  });

  // -- the frames

  // Decoded off the page's thread (createImageBitmap) and drawn on the canvas, newest only.
  const canvas = face.getContext("2d");
  let asked = 0;
  let drawnNumber = 0;
  function showFrame(blob) {
    const number = ++asked;
    createImageBitmap(blob).then((bitmap) => {
      if (number < drawnNumber) return bitmap.close(); // a newer one was drawn first
      drawnNumber = number;
      if (face.width !== bitmap.width || face.height !== bitmap.height) {
        face.width = bitmap.width;
        face.height = bitmap.height;
        placePrompt();
      }
      canvas.drawImage(bitmap, 0, 0);
      bitmap.close();
      face.hidden = false;
      shown.frames += 1;
      shown.lastFrameAt = performance.now();
    }, () => {});
  }

  // The 'Tap for sound' prompt sits in the lower left corner of the face, on plain skin, or on the
  // black bar below a letterboxed face where the bar holds it (a portrait window): a bar thinner
  // than the prompt (a 1280x800 tablet's, 25 px) would put half of it on the face's edge.
  function placePrompt() {
    if (!face.width) return;
    const drawnHeight = Math.min(innerHeight, (innerWidth * face.height) / face.width);
    const bar = (innerHeight - drawnHeight) / 2;
    const margin = Math.max(8, 0.02 * Math.min(innerWidth, innerHeight));
    const onBar = bar >= tap.offsetHeight + 2 * margin;
    tap.style.bottom = `${(onBar ? 0 : bar) + margin}px`;
  }
  addEventListener("resize", placePrompt);

  // -- the sound: a tap lets it in where the browser asks for one

  const voice = window.BaxterSound({
    token,
    needsTap: (needed) => {
      tap.hidden = !needed;
      placePrompt(); // its height known once shown
    },
  });
  shown.started = voice.started;

  // -- awake: the Screen Wake Lock API, asked again whenever the page is shown again

  let lock = null;
  async function keepAwake() {
    if (!("wakeLock" in navigator)) {
      shown.awake = window.isSecureContext
        ? "no wake lock in this browser"
        : "no wake lock: the browser gives it to https and this machine's own pages only";
      return;
    }
    if (lock !== null || document.visibilityState !== "visible") return;
    try {
      lock = await navigator.wakeLock.request("screen");
      shown.awake = "held";
      lock.addEventListener("release", () => {
        lock = null;
        shown.awake = "released";
      });
    } catch (e) {
      shown.awake = `refused: ${e.name}`; // asked again at the next tap or showing
    }
  }
  document.addEventListener("visibilitychange", keepAwake);

  // A tap (or a click, or a key) lets sound in, asks for the whole screen, and for the wake lock
  // where the browser wanted a gesture for it.
  function touched() {
    voice.wake();
    keepAwake();
    const root = document.documentElement;
    if (!document.fullscreenElement && root.requestFullscreen) root.requestFullscreen().catch(() => {});
  }
  document.addEventListener("pointerdown", touched);
  document.addEventListener("keydown", touched);

  // -- a tap on the face raises `touch` for the script's handlers. The page says only where, as
  // fractions of the frame (drawn letterboxed: object-fit contain); the server finds what is there.
  const TOUCHES_KEPT = 20;
  function tapped(event) {
    if (event.target === tap || face.hidden || !face.width) return;
    const where = window.baxterfaceTapAt(face, face.width, face.height, event);
    const headers = { "content-type": "application/json" };
    if (token) headers["x-baxterface-token"] = token;
    fetch("/api/touch", { method: "POST", headers, body: JSON.stringify(where) })
      .then((answer) => (answer.ok ? answer.json() : null))
      .then((answer) => {
        if (!answer) return;
        shown.touches.push(answer.event);
        if (shown.touches.length > TOUCHES_KEPT) shown.touches.shift();
      })
      .catch(() => {});
  }
  document.addEventListener("pointerdown", tapped);

  // -- the connection: frames and status, and back again after a restart

  let socket = null;
  let heard = 0;
  let tries = 0;
  let lost = null;

  function connect() {
    const scheme = location.protocol === "https:" ? "wss" : "ws";
    const query = token ? "?token=" + encodeURIComponent(token) : "";
    const ws = new WebSocket(`${scheme}://${location.host}/api/live${query}`);
    socket = ws;
    ws.binaryType = "blob";
    ws.onopen = () => {
      heard = performance.now();
      tries = 0;
      shown.connected = true;
      shown.connections += 1;
      clearTimeout(lost);
      offline.hidden = true;
    };
    ws.onmessage = (event) => {
      heard = performance.now();
      if (typeof event.data !== "string") {
        shown.received += 1;
        shown.lastReceivedAt = performance.now();
        shown.bytes += event.data.size;
        shown.frameBytes += event.data.size;
        showFrame(event.data);
        return;
      }
      shown.bytes += event.data.length;
      const message = JSON.parse(event.data);
      if (message.kind === "status") voice.play(message, performance.now());
    };
    ws.onclose = () => closed(ws);
  }

  function closed(ws) {
    if (ws !== socket) return;
    socket = null;
    if (shown.connected) {
      shown.connected = false;
      voice.silence();
      lost = setTimeout(() => (offline.hidden = false), OFFLINE_AFTER);
    }
    setTimeout(connect, RETRY[Math.min(tries, RETRY.length - 1)]);
    tries += 1;
  }

  // A connection that went quiet (the network dropped, and no close came): a new one.
  setInterval(() => {
    if (socket && socket.readyState === WebSocket.OPEN && performance.now() - heard > SILENT) {
      const ws = socket;
      ws.onclose = null;
      ws.close();
      closed(ws);
    }
  }, 1000);

  voice.wake(); // a browser that allows sound without a tap: ready now; one that does not: asks
  tap.hidden = voice.state() === "running";
  keepAwake();
  connect();
})();
