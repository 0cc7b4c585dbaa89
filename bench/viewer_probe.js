// bench/viewer.py's probe in the viewer's page: it moves the camera as a user does, with pointer and key
// events dispatched to the page's own handlers, and logs each frame when it reaches the image element
// (id "view"), with what window.mbaoView.state() then says of it. Times are performance.now(), in ms.
"use strict";

window.viewerProbe = (() => {
  const view = document.getElementById("view");
  const frames = [];
  const images = [];  // the bytes of the frames shown while `capturing`: promises, settled before a result
  let capturing = false;

  // Runs after the page's onBinary, which sets the image's src and then the state, in the same task.
  new MutationObserver(() => {
    const s = window.mbaoView.state();
    const frame = { t: performance.now(), received: s.received, camera: s.frame_camera, width: s.width,
                    height: s.height, frame_ms: s.last_frame_ms, frames: s.frames };
    // Fetched now: the page revokes this URL when the next frame comes.
    if (capturing) images.push(dataUrl(view.src).then((url) => { frame.png = url; }));
    frames.push(frame);
  }).observe(view, { attributes: true, attributeFilter: ["src"] });

  const sleep = (ms) => new Promise((resolve) => setTimeout(resolve, ms));

  async function dataUrl(src) {
    const blob = await (await fetch(src)).blob();
    return new Promise((resolve) => {
      const reader = new FileReader();
      reader.onload = () => resolve(reader.result);
      reader.readAsDataURL(blob);
    });
  }

  function centre() {
    const box = view.getBoundingClientRect();
    return [box.left + box.width / 2, box.top + box.height / 2];
  }

  function pointer(type, x, y) {
    view.dispatchEvent(new PointerEvent(type, {
      bubbles: true, cancelable: true, pointerId: 1, pointerType: "mouse", isPrimary: true, clientX: x, clientY: y,
      button: 0, buttons: type === "pointerup" ? 0 : 1,
    }));
  }

  // A pointer move: when it was made, and the camera the page then holds (it sends it at its next animation frame).
  function move(x, y) {
    const t = performance.now();
    pointer("pointermove", x, y);
    return { t, camera: window.mbaoView.state().camera };
  }

  const sameCamera = (a, b) => a !== null && b !== null && ["eye", "target", "up"].every(
    (key) => a[key].every((v, i) => Math.abs(v - b[key][i]) <= 1e-5 * Math.max(1, Math.abs(v))));

  // A drag along a circle of `radius` pixels from the image's centre, one turn every `period` s, with a pointer
  // move every 1/hz s, held for `seconds`. Its frames, and for each move the ms until the first frame that
  // shows it or a later move (the page sends the latest camera; moves it skips show in the next frame),
  // looked for until `after` s past the release, which sends the last camera as a still view.
  async function drag(seconds, hz, radius, period, after) {
    const [x0, y0] = centre();
    const moves = [];
    pointer("pointerdown", x0, y0);
    const down = performance.now(), receivedAtDown = window.mbaoView.state().received;
    await new Promise((resolve) => {
      const timer = setInterval(() => {
        const angle = (2 * Math.PI * (performance.now() - down)) / (period * 1000);
        if (performance.now() - down >= seconds * 1000) {
          clearInterval(timer);
          resolve();
          return;
        }
        moves.push(move(x0 + radius * Math.sin(angle), y0 + radius * (1 - Math.cos(angle))));
      }, 1000 / hz);
    });
    const up = performance.now(), received = window.mbaoView.state().received - receivedAtDown;
    pointer("pointerup", x0, y0);
    await sleep(after * 1000);
    const later = frames.filter((f) => f.t >= down);
    // The move each frame shows: the latest one whose camera it has (none: a camera from before the drag).
    const shows = later.map((f) => moves.findLastIndex((m) => m.t <= f.t && sameCamera(m.camera, f.camera)));
    const latencies = moves.map((m, i) => {
      const k = later.findIndex((f, j) => f.t >= m.t && shows[j] >= i);
      return k < 0 ? null : later[k].t - m.t;
    });
    return { seconds: (up - down) / 1000, moves: moves.length, received, latencies,
             frames: later.filter((f) => f.t <= up) };
  }

  // Waits for the first frame after `since` that shows `camera`, for at most `timeout` ms.
  async function frameShowing(camera, since, timeout) {
    while (performance.now() - since < timeout) {
      const frame = frames.find((f) => f.t >= since && sameCamera(f.camera, camera));
      if (frame) return frame;
      await sleep(5);
    }
    return null;
  }

  // With the pointer held, one move of `step` pixels after each pause (ms), to the right and back in turn, and
  // each waits for its frame (none shows the camera before, the same as the one after). Each result is that
  // frame, its `ms` after the move, or null.
  async function inputs(pauses, step, timeout) {
    const [x0, y0] = centre();
    const results = [];
    pointer("pointerdown", x0, y0);
    for (const [i, pause] of pauses.entries()) {
      await sleep(pause);
      const input = move(i % 2 === 0 ? x0 + step : x0, y0);
      const frame = await frameShowing(input.camera, input.t, timeout);
      results.push(frame && { ...frame, ms: frame.t - input.t });
    }
    pointer("pointerup", x0, y0);
    return results;
  }

  // A drag away, released, then the home key: the camera stops at home. The frames of the next `seconds`,
  // each with its image and `t` after the key press, and the home camera.
  async function stop(seconds) {
    await drag(0.5, 60, 60, 4, 0.3);
    capturing = true;
    const pressed = performance.now();
    document.dispatchEvent(new KeyboardEvent("keydown", { key: "h", bubbles: true }));
    await sleep(seconds * 1000);
    capturing = false;
    await Promise.all(images.splice(0));
    const shown = frames.filter((f) => f.t >= pressed && f.t <= pressed + seconds * 1000);
    return { home: window.mbaoView.state().camera, frames: shown.map((f) => ({ ...f, t: f.t - pressed })) };
  }

  return { drag, inputs, stop };
})();
