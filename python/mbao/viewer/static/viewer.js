// The mbao view page: shows the frames the server sends, and sends it the
// camera and settings as the user changes them (docs/viewer.md has the protocol).
"use strict";

(() => {
  const view = document.getElementById("view");
  const form = document.getElementById("controls");
  const errorBox = document.getElementById("error");
  const UNLIMITED = "inf";  // JSON has no infinity: an unlimited radius travels as this string

  const state = {
    camera: null, settings: null, home: null, radius: 1, defaultRadius: UNLIMITED,
    frames: 0, final: false, received: 0, last_frame_ms: null, width: 0, height: 0, error: null,
    frame_camera: null,  // the camera of the frame shown, as its header gives it (state.camera may be ahead)
  };
  let socket = null;
  let sent = 0;  // messages sent on this socket, as the server counts them (a frame's messages_read)
  let pendingCamera = false;  // a camera change waits for the next animation frame
  let wheelTimer = null;

  // Vectors.
  const sub = (a, b) => a.map((v, i) => v - b[i]);
  const add = (a, b) => a.map((v, i) => v + b[i]);
  const scale = (a, s) => a.map((v) => v * s);
  const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
  const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
  const norm = (a) => Math.hypot(a[0], a[1], a[2]);
  const unit = (a) => scale(a, 1 / norm(a));
  // `a` turned by `angle` about the unit axis `k` (Rodrigues).
  const rotate = (a, k, angle) => {
    const c = Math.cos(angle), s = Math.sin(angle);
    return add(add(scale(a, c), scale(cross(k, a), s)), scale(k, dot(k, a) * (1 - c)));
  };

  // Camera moves, in pixels of the image as shown.
  function orbit(camera, dx, dy) {
    const up = unit(camera.up);
    let offset = rotate(sub(camera.eye, camera.target), up, -dx * 0.008);
    const right = unit(cross(offset, up));
    const pitched = rotate(offset, right, dy * 0.008);
    // Stop short of the poles, where "up" would flip.
    if (Math.abs(dot(unit(pitched), up)) < 0.995) offset = pitched;
    return { ...camera, eye: add(camera.target, offset) };
  }

  function pan(camera, dx, dy) {
    const forward = sub(camera.target, camera.eye);
    const right = unit(cross(forward, camera.up));
    const up = unit(cross(right, forward));
    const perPixel = (2 * norm(forward) * Math.tan((camera.vfov_deg * Math.PI) / 360)) / view.clientHeight;
    const move = add(scale(right, -dx * perPixel), scale(up, dy * perPixel));
    return { ...camera, eye: add(camera.eye, move), target: add(camera.target, move) };
  }

  function zoom(camera, wheelDelta) {
    const factor = Math.exp(wheelDelta * 0.0015);
    return { ...camera, eye: add(camera.target, scale(sub(camera.eye, camera.target), factor)) };
  }

  // Messages.
  function send(message) {
    if (socket && socket.readyState === WebSocket.OPEN) {
      socket.send(JSON.stringify(message));
      sent += 1;
    }
  }

  function sendView(changes, interactive) {
    state.final = false;  // a new view: its frames are to come
    state.error = null;
    errorBox.hidden = true;
    send({ type: "set", ...changes, interactive });
  }

  function setCamera(camera, interactive) {
    state.camera = camera;
    if (interactive) {
      // Coalesce moves to one message per animation frame: the latest camera wins.
      if (!pendingCamera) {
        pendingCamera = true;
        requestAnimationFrame(() => { pendingCamera = false; sendView({ camera: state.camera }, true); });
      }
    } else {
      sendView({ camera }, false);
    }
  }

  function setSettings(changes) {
    state.settings = { ...state.settings, ...changes };
    showSettings();
    sendView({ settings: changes }, false);
  }

  function onText(message) {
    if (message.type === "hello") {
      state.home = message.home;
      state.camera = message.camera;
      state.settings = message.settings;
      state.radius = message.scene.radius;
      state.defaultRadius = message.scene.default_radius;
      buildControls(message.specs);
      showSettings();
      text("device", message.device);
      const file = message.scene.name.split(/[\\/]/).pop();  // a loaded scene's name is its path
      text("scene", `${file} (${message.scene.triangles.toLocaleString()} triangles)`);
      sendView({ camera: state.camera }, false);
    } else if (message.type === "state") {
      state.camera = message.camera;
      state.settings = message.settings;
      showSettings();
    } else if (message.type === "error") {
      state.error = message.message;
      errorBox.textContent = message.message;
      errorBox.hidden = false;
    } else if (message.type === "picked" && message.point) {
      setCamera({ ...state.camera, target: message.point }, false);
    }
  }

  function onBinary(buffer) {
    const length = new DataView(buffer).getUint32(0, true);
    const header = JSON.parse(new TextDecoder().decode(new Uint8Array(buffer, 4, length)));
    const body = new Uint8Array(buffer, 4 + length);
    if (header.type === "file") {
      download(header.name, new Blob([body], { type: header.mime }));
      return;
    }
    const old = view.src;
    view.src = URL.createObjectURL(new Blob([body], { type: header.format === "png" ? "image/png" : "image/jpeg" }));
    if (old.startsWith("blob:")) URL.revokeObjectURL(old);
    state.received += 1;
    state.frames = header.frames;
    // A final frame of a view taken before the server read our last message is not this view's.
    state.final = header.final && header.messages_read === sent;
    state.last_frame_ms = header.frame_ms;
    state.width = header.width;
    state.height = header.height;
    state.frame_camera = header.camera;
    text("frame-ms", `${header.frame_ms.toFixed(1)} ms` + (header.moving ? " (moving)" : ""));
    text("mrays", header.mrays_per_s == null ? "\u2013" : `${header.mrays_per_s.toFixed(2)} Mrays/s`);
    text("frames", `${header.frames}` + (header.final ? " (done)" : ""));
    text("std-error", header.standard_error == null ? "\u2013" : header.standard_error.toFixed(4));
    text("size", `${header.width} \u00d7 ${header.height}`);
  }

  function download(name, blob) {
    const link = document.createElement("a");
    link.href = URL.createObjectURL(blob);
    link.download = name;
    link.click();
    setTimeout(() => URL.revokeObjectURL(link.href), 10000);
  }

  function text(id, value) {
    document.getElementById(id).textContent = value;
  }

  // Controls: each named after its setting.
  function buildControls(specs) {
    for (const spec of specs) {
      const control = form.elements.namedItem(spec.name);
      if (control && control.tagName === "SELECT") {
        control.replaceChildren(...spec.choices.map((choice) => new Option(choice, choice)));
      }
    }
  }

  // The radius slider is log10 of the radius over the scene's.
  const radiusFromSlider = (value) => state.radius * Math.pow(10, value);
  const sliderFromRadius = (radius) => Math.log10(radius / state.radius);

  function showSettings() {
    const s = state.settings;
    for (const control of form.elements) {
      if (!control.name || !(control.name in s)) continue;
      if (control.name === "max_distance") continue;
      if (control.type === "checkbox") control.checked = s[control.name];
      else control.value = s[control.name];
    }
    // Unset, the radius is the camera's suggestion, else unlimited (SPEC 1).
    const shown = s.max_distance === null ? state.defaultRadius : s.max_distance;
    const unlimited = shown === UNLIMITED;
    const radius = unlimited ? state.radius : shown;
    document.getElementById("unlimited").checked = unlimited;
    form.elements.max_distance.disabled = unlimited;
    if (!unlimited) form.elements.max_distance.value = sliderFromRadius(radius);
    form.querySelector('output[for="rho"]').textContent = Number(s.rho).toFixed(2);
    form.querySelector('output[for="max_distance"]').textContent = unlimited ? "\u221e" : radius.toPrecision(3);
  }

  function controlValue(control) {
    if (control.type === "checkbox") return control.checked;
    if (control.name === "max_distance") return radiusFromSlider(Number(control.value));
    if (control.type === "number" || control.type === "range") return Number(control.value);
    return control.value;
  }

  form.addEventListener("change", (event) => {
    const control = event.target;
    if (control.id === "unlimited") {
      setSettings({ max_distance: control.checked ? UNLIMITED : radiusFromSlider(Number(form.elements.max_distance.value)) });
    } else if (control.name) {
      setSettings({ [control.name]: controlValue(control) });
    }
  });
  form.addEventListener("input", (event) => {
    if (event.target.type === "range") {
      const radius = radiusFromSlider(Number(form.elements.max_distance.value));
      form.querySelector('output[for="rho"]').textContent = Number(form.elements.rho.value).toFixed(2);
      form.querySelector('output[for="max_distance"]').textContent = radius.toPrecision(3);
    }
  });
  form.addEventListener("submit", (event) => event.preventDefault());
  document.getElementById("home").addEventListener("click", () => setCamera(state.home, false));
  for (const button of form.querySelectorAll("[data-save]")) {
    button.addEventListener("click", () => send({ type: "save", what: button.dataset.save }));
  }
  document.addEventListener("keydown", (event) => {
    if ((event.key === "h" || event.key === "H") && !(event.target instanceof HTMLInputElement)) {
      setCamera(state.home, false);
    }
  });

  // The mouse.
  let drag = null;
  view.addEventListener("contextmenu", (event) => event.preventDefault());
  view.addEventListener("pointerdown", (event) => {
    if (!state.camera) return;
    view.setPointerCapture(event.pointerId);
    drag = { x: event.clientX, y: event.clientY, pan: event.button === 2 || event.shiftKey };
  });
  view.addEventListener("pointermove", (event) => {
    if (!drag) return;
    const dx = event.clientX - drag.x, dy = event.clientY - drag.y;
    drag.x = event.clientX;
    drag.y = event.clientY;
    setCamera(drag.pan ? pan(state.camera, dx, dy) : orbit(state.camera, dx, dy), true);
  });
  const release = () => {
    if (!drag) return;
    drag = null;
    setCamera(state.camera, false);
  };
  view.addEventListener("pointerup", release);
  view.addEventListener("pointercancel", release);
  view.addEventListener("wheel", (event) => {
    event.preventDefault();
    if (!state.camera) return;
    setCamera(zoom(state.camera, event.deltaY), true);
    clearTimeout(wheelTimer);
    wheelTimer = setTimeout(() => setCamera(state.camera, false), 200);
  }, { passive: false });
  view.addEventListener("dblclick", (event) => {
    const box = view.getBoundingClientRect();
    send({ type: "pick", x: (event.clientX - box.left) / box.width, y: (event.clientY - box.top) / box.height });
  });

  // The socket.
  function connect() {
    const url = new URL("ws", window.location.href);
    url.protocol = url.protocol === "https:" ? "wss:" : "ws:";
    socket = new WebSocket(url);
    sent = 0;
    socket.binaryType = "arraybuffer";
    socket.onmessage = (event) => (typeof event.data === "string" ? onText(JSON.parse(event.data)) : onBinary(event.data));
    socket.onclose = () => {
      state.error = "the connection to the server is closed";
      errorBox.textContent = state.error;
      errorBox.hidden = false;
    };
  }

  // The automation surface (docs/viewer.md).
  window.mbaoView = {
    state: () => JSON.parse(JSON.stringify({
      camera: state.camera, settings: state.settings, frames: state.frames, final: state.final,
      received: state.received,
      last_frame_ms: state.last_frame_ms, width: state.width, height: state.height, error: state.error,
      frame_camera: state.frame_camera,
    })),
    set: ({ camera, settings } = {}) => {
      const changes = {};
      if (camera) changes.camera = state.camera = { ...state.camera, ...camera };
      if (settings) {
        changes.settings = settings;
        state.settings = { ...state.settings, ...settings };
        showSettings();
      }
      sendView(changes, false);
    },
    // A message as it is: for scripts and tests of the protocol.
    sendRaw: (textMessage) => {
      socket.send(textMessage);
      sent += 1;
    },
  };

  connect();
})();
