// wgpurender's page player: replays a recording of the wgpu path (data.js, made by `wgpurender export`) on the
// browser's WebGPU. It knows no stage and no scene: it creates the recorded objects, replays the recorded
// frame with each frame's recorded uploads, copies the frame to the canvas, and (for a 3D scene) packs the
// orbit camera's view matrix and eye into the Camera uniform at the offsets the export wrote down.
// Hook for tests: window.wgpurender.capture(options) -> Promise<{width, height, rgba}> (base64 RGBA8, top row
// first) of the frame at t = 0 and the default camera ({time: T} or {current: true} ask for another one);
// window.wgpurender.adapter: the adapter's info. A classic script (no ES module): pages open from file://.
(function () {
  "use strict";
  const X = window.WGPURENDER_EXPORT;
  const meta = X.meta;
  const api = { adapter: null, error: null, frames: 0, sample: 0, frameMs: null, samplesSeen: new Set() };
  window.wgpurender = api;
  const $ = (id) => document.getElementById(id);
  const blobs = [];
  const bytesOf = (text) => Uint8Array.from(atob(text), (c) => c.charCodeAt(0));
  const blob = (i) => blobs[i] || (blobs[i] = bytesOf(X.blobs[i]));

  // -- PNG (webpage/packing.py): textures and the reference frame. Decoded here to their exact bytes (inflate with
  // DecompressionStream, then undo each row's filter); a canvas would premultiply alpha and change them.
  async function inflate(parts) {
    const stream = new Blob(parts).stream().pipeThrough(new DecompressionStream("deflate"));
    return new Uint8Array(await new Response(stream).arrayBuffer());
  }

  async function decodePng(text) {
    const png = bytesOf(text), view = new DataView(png.buffer);
    let pos = 8, width = 0, height = 0;
    const idat = [];
    while (pos < png.length) {
      const length = view.getUint32(pos), type = String.fromCharCode(...png.subarray(pos + 4, pos + 8));
      if (type === "IHDR") {
        width = view.getUint32(pos + 8);
        height = view.getUint32(pos + 12);
        if (png[pos + 16] !== 8 || png[pos + 17] !== 6 || png[pos + 20] !== 0) throw new Error("not an 8-bit RGBA PNG");
      } else if (type === "IDAT") idat.push(png.subarray(pos + 8, pos + 8 + length));
      pos += 12 + length;
    }
    const raw = await inflate(idat), stride = width * 4, out = new Uint8Array(stride * height);
    for (let y = 0; y < height; y++) {
      const filter = raw[y * (stride + 1)], line = y * (stride + 1) + 1, o = y * stride;
      for (let x = 0; x < stride; x++) {
        const a = x >= 4 ? out[o + x - 4] : 0, b = y ? out[o - stride + x] : 0, c = x >= 4 && y ? out[o - stride + x - 4] : 0;
        const p = a + b - c, pa = Math.abs(p - a), pb = Math.abs(p - b), pc = Math.abs(p - c);
        const predict = [0, a, b, (a + b) >> 1, pa <= pb && pa <= pc ? a : pb <= pc ? b : c][filter];
        out[o + x] = (raw[line + x] + predict) & 255;
      }
    }
    return out;
  }

  async function decodeBlobs() {
    await Promise.all(X.blobs.map(async (b, i) => { if (typeof b !== "string") blobs[i] = await decodePng(b.png); }));
  }
  const objects = [];

  function fail(text) {
    api.error = text;
    $("message").textContent = text;
    $("adapter").textContent = "none";
    $("view").style.display = "none";
  }

  // A WebGPU validation error or a lost device after start: say so on the page and stop drawing (a blank canvas
  // with a ticking frame time and a "may differ within the spec" caption said nothing was wrong).
  function broken(text) {
    if (api.stopped) return;
    api.stopped = true;
    api.error = text;
    console.error(text);
    $("message").textContent = text;
    $("frametime").textContent = "stopped";
    $("difference").textContent = "not compared: the page hit a WebGPU error";
  }

  function resolve(value, blobFor) {
    if (Array.isArray(value)) return value.map((v) => resolve(v, blobFor));
    if (value && typeof value === "object") {
      if ("$" in value) return objects[value.$];
      if ("#" in value) return blobFor(value["#"]);
      const out = {};
      for (const k in value) out[k] = resolve(value[k], blobFor);
      return out;
    }
    return value;
  }

  function run(call, blobFor) {
    const target = objects[call.o];
    let result;
    if (call.g) {
      result = target[call.g];
    } else if (call.d) {
      const d = resolve(call.d, blobFor);
      if (call.m === "createBufferWithData") {
        result = target.createBuffer({ label: d.label, usage: d.usage, size: (d.data.byteLength + 3) & ~3,
                                       mappedAtCreation: true });
        new Uint8Array(result.getMappedRange()).set(d.data);
        result.unmap();
      } else {
        if (call.m === "createBindGroup") {
          d.entries = d.entries.map((e) => (e.resource instanceof GPUBuffer ? { ...e, resource: { buffer: e.resource } } : e));
        }
        result = target[call.m](d);
      }
    } else {
      const args = resolve(call.a, blobFor).map((v) => (v === null ? undefined : v));
      while (args.length && args[args.length - 1] === undefined) args.pop();
      result = target[call.m](...args);
    }
    if (call.r !== undefined) objects[call.r] = result;
  }

  // -- the orbit camera (wgpurender/core/view/orbit.py and transforms.look_at, for the page) -----------------------
  const sub = (a, b) => a.map((v, i) => v - b[i]);
  const dot = (a, b) => a.reduce((s, v, i) => s + v * b[i], 0);
  const scale = (a, s) => a.map((v) => v * s);
  const unit = (a) => scale(a, 1 / Math.hypot(...a));
  const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
  const MAX_PITCH = (89 * Math.PI) / 180, PER_PIXEL = (0.4 * Math.PI) / 180, ZOOM = 0.9;

  function makeOrbit(o) {
    const up = unit(o.up), offset = sub(o.eye, o.target), distance = Math.hypot(...offset);
    let horizontal = sub(offset, scale(up, dot(offset, up)));
    if (Math.hypot(...horizontal) < 1e-9 * distance) horizontal = cross(up, Math.abs(up[0]) < 0.9 ? [1, 0, 0] : [0, 0, 1]);
    const a = unit(horizontal), b = cross(up, a);
    const pitch = Math.max(-MAX_PITCH, Math.min(MAX_PITCH, Math.asin(Math.max(-1, Math.min(1, dot(offset, up) / distance)))));
    const start = { yaw: 0, pitch, distance };
    const orbit = { target: o.target, up: o.up, a, b, ...start, moved: false };
    orbit.eye = () => {
      const cp = Math.cos(orbit.pitch);
      const dir = [0, 1, 2].map((i) => cp * (Math.cos(orbit.yaw) * a[i] + Math.sin(orbit.yaw) * b[i]) + Math.sin(orbit.pitch) * up[i]);
      return orbit.target.map((t, i) => t + orbit.distance * dir[i]);
    };
    orbit.reset = () => Object.assign(orbit, start, { moved: false });
    return orbit;
  }

  function lookAt(eye, target, up) {  // column-major mat4x4f, as uniforms.Struct packs a row-major numpy matrix
    const f = unit(sub(target, eye)), s = unit(cross(f, up)), u = cross(s, f);
    const rows = [s, u, scale(f, -1)];
    const m = new Float32Array(16);
    for (let r = 0; r < 3; r++) {
      for (let c = 0; c < 3; c++) m[c * 4 + r] = rows[r][c];
      m[12 + r] = -dot(rows[r], eye);
    }
    m[15] = 1;
    return m;
  }

  // -- frames --------------------------------------------------------------------------------------------------
  let device, canvasContext, orbit = null, cameraDefault = null;

  function writeCamera(useDefault) {
    const cam = meta.orbit && meta.orbit.camera;
    if (!cam) return;
    if (useDefault || !orbit.moved) {
      device.queue.writeBuffer(objects[cam.buffer], 0, cameraDefault);
      return;
    }
    const eye = orbit.eye();
    device.queue.writeBuffer(objects[cam.buffer], cam.fields.view, lookAt(eye, orbit.target, orbit.up));
    // an orthographic camera's eye is the direction towards it with w = 0 (Camera.eye_vector)
    const eyeVector = meta.orbit.orthographic ? [...unit(sub(eye, orbit.target)), 0] : [...eye, 1];
    device.queue.writeBuffer(objects[cam.buffer], cam.fields.eye, new Float32Array(eyeVector));
  }

  function drawFrame(sample, useDefaultCamera) {
    writeCamera(useDefaultCamera);
    const data = X.samples[sample];
    let k = 0;
    for (const call of X.frame) {
      const upload = call.m === "writeBuffer" || call.m === "writeTexture";
      const slot = upload ? k++ : -1;
      run(call, (i) => (upload && (call.m === "writeBuffer" ? call.a[2] : call.a[1])["#"] === i ? blob(data[slot]) : blob(i)));
    }
  }

  async function readPixels() {  // the target's RGBA8 bytes, top row first
    const [w, h] = meta.size, bpr = Math.ceil((w * 4) / 256) * 256;
    const buffer = device.createBuffer({ size: bpr * h, usage: GPUBufferUsage.COPY_DST | GPUBufferUsage.MAP_READ });
    const encoder = device.createCommandEncoder();
    encoder.copyTextureToBuffer({ texture: objects[meta.target] }, { buffer, bytesPerRow: bpr, rowsPerImage: h }, [w, h, 1]);
    device.queue.submit([encoder.finish()]);
    await buffer.mapAsync(GPUMapMode.READ);
    const padded = new Uint8Array(buffer.getMappedRange()), rgba = new Uint8ClampedArray(w * h * 4);
    for (let y = 0; y < h; y++) rgba.set(padded.subarray(y * bpr, y * bpr + w * 4), y * w * 4);
    buffer.unmap();
    buffer.destroy();
    return rgba;
  }

  // Presenting: copy the frame into a WebGPU canvas (index.html#webgpu-canvas), or by default read it back and
  // draw it on a 2D canvas. Headless Chromium (SwiftShader) loses its WebGPU instance as soon as a WebGPU
  // canvas texture is used ("A valid external Instance reference no longer exists"), and the readback works
  // in every browser; at course sizes it costs a few milliseconds.
  const webgpuCanvas = location.hash === "#webgpu-canvas";
  async function present() {
    if (webgpuCanvas) {
      const encoder = device.createCommandEncoder();
      encoder.copyTextureToTexture({ texture: objects[meta.target] }, { texture: canvasContext.getCurrentTexture() },
                                   [meta.size[0], meta.size[1], 1]);
      device.queue.submit([encoder.finish()]);
      await device.queue.onSubmittedWorkDone();
      return;
    }
    canvasContext.putImageData(new ImageData(await readPixels(), meta.size[0], meta.size[1]), 0, 0);
  }

  api.capture = async function (options = {}) {
    if (api.error) throw new Error(api.error);
    await api.ready;
    const sample = options.time ? Math.floor(options.time * meta.fps) % X.samples.length : 0;
    drawFrame(sample, !options.current);
    const rgba = await readPixels();
    let text = "";
    for (let i = 0; i < rgba.length; i += 0x8000) text += String.fromCharCode.apply(null, rgba.subarray(i, i + 0x8000));
    return { width: meta.size[0], height: meta.size[1], rgba: btoa(text) };
  };

  // A PNG of data.js decoded as the page decodes it (base64 bytes), for a test against another decoder.
  api.decodePng = async (text) => {
    const bytes = await decodePng(text);
    let out = "";
    for (let i = 0; i < bytes.length; i += 0x8000) out += String.fromCharCode.apply(null, bytes.subarray(i, i + 0x8000));
    return btoa(out);
  };

  // The orbit's view matrix now (column-major), for a test against the Python look-at.
  api.orbitView = () => (orbit ? Array.from(lookAt(orbit.eye(), orbit.target, orbit.up)) : null);

  function controls(canvas) {
    let last = null;
    canvas.addEventListener("pointerdown", (e) => { last = [e.clientX, e.clientY]; canvas.setPointerCapture(e.pointerId); });
    canvas.addEventListener("pointerup", () => { last = null; });
    canvas.addEventListener("pointermove", (e) => {
      if (!last) return;
      orbit.yaw -= (e.clientX - last[0]) * PER_PIXEL;
      orbit.pitch = Math.max(-MAX_PITCH, Math.min(MAX_PITCH, orbit.pitch + (e.clientY - last[1]) * PER_PIXEL));
      last = [e.clientX, e.clientY];
      orbit.moved = true;
    });
    canvas.addEventListener("wheel", (e) => { e.preventDefault(); orbit.distance *= ZOOM ** (e.deltaY < 0 ? 1 : -1); orbit.moved = true; });
    canvas.addEventListener("dblclick", () => orbit.reset());
  }

  function loop(start) {
    const tick = async (now) => {
      const t0 = performance.now();
      api.sample = Math.max(0, Math.floor(((now - start) / 1000) * meta.fps)) % X.samples.length;
      drawFrame(api.sample, false);
      await present();
      if (api.stopped) return;  // a WebGPU error: the loop ends (a frame in flight then is not counted)
      api.frameMs = performance.now() - t0;
      api.frames += 1;
      if (api.frames === 1) api.firstPixelMs = performance.now();  // since navigation start: the first frame shown
      api.samplesSeen.add(api.sample);
      if (api.frames % 10 === 1) $("frametime").textContent = `${api.frameMs.toFixed(2)} ms (replay, GPU, present)`;
      requestAnimationFrame(tick);
    };
    requestAnimationFrame(tick);
  }

  async function main() {
    if (!navigator.gpu) return fail("This browser has no WebGPU (navigator.gpu is missing): use a browser with " +
      "WebGPU enabled, e.g. Chromium with --enable-unsafe-webgpu, or a current Chrome, Edge or Firefox.");
    const adapter = await navigator.gpu.requestAdapter();
    if (!adapter) return fail("WebGPU is present but gave no adapter: enable WebGPU for this device " +
      "(Chromium: --enable-unsafe-webgpu) or try another browser.");
    const info = adapter.info || {};
    api.adapter = { vendor: info.vendor, architecture: info.architecture, device: info.device, description: info.description };
    $("adapter").textContent = [info.vendor, info.architecture, info.device, info.description].filter(Boolean).join(" / ");
    api.gpuAdapter = adapter;  // kept: Chromium fails later async work with "no valid external Instance" otherwise
    device = await adapter.requestDevice();
    api.device = device;
    device.addEventListener("uncapturederror", (e) => broken("WebGPU error: " + e.error.message +
      " (the picture is not to be trusted; the browser's console has the details)"));
    device.lost.then((info) => broken(`The WebGPU device was lost (${info.reason || "unknown reason"}): ` +
      `${(info.message || "no message").replace(/\.+$/, "")}. Reload the page to start again.`));
    objects[meta.device] = device;
    $("plan").textContent += `\nthis page's adapter: ${$("adapter").textContent || "unnamed"}` +
      (info.isFallbackAdapter ? " (a fallback, software adapter)" : "");
    await decodeBlobs();
    device.pushErrorScope("validation");
    for (const call of X.setup) run(call, blob);
    const setupError = await device.popErrorScope();
    if (setupError) return broken("WebGPU error while setting up: " + setupError.message);
    const cam = meta.orbit && meta.orbit.camera;
    if (cam) {
      const writes = X.setup.filter((c) => c.m === "writeBuffer" && c.a[0].$ === cam.buffer);
      cameraDefault = blob(writes[writes.length - 1].a[2]["#"]);
      orbit = makeOrbit(meta.orbit);
    }
    const canvas = $("view");
    canvasContext = canvas.getContext(webgpuCanvas ? "webgpu" : "2d");
    if (webgpuCanvas) {
      canvasContext.configure({ device, format: meta.format.replace("-srgb", ""), alphaMode: "opaque",
                                usage: GPUTextureUsage.RENDER_ATTACHMENT | GPUTextureUsage.COPY_DST });
    }
    if (orbit) controls(canvas);
    loop(performance.now());
    compareWithWgpuNative();
  }

  // This page's t = 0 frame against wgpu-native's frame of the same recording (data.js "reference").
  async function compareWithWgpuNative() {
    if (!X.reference || api.stopped) return;
    drawFrame(0, true);
    const mine = await readPixels(), theirs = await decodePng(X.reference.png);
    if (api.stopped) return;
    let max = 0, over = 0;
    for (let i = 0; i < mine.length; i += 4) {
      let d = 0;
      for (let c = 0; c < 4; c++) d = Math.max(d, Math.abs(mine[i + c] - theirs[i + c]));
      max = Math.max(max, d);
      if (d > 1) over += 1;
    }
    const share = (100 * over) / (mine.length / 4);
    api.difference = { max, over1: share / 100 };
    $("difference").textContent = max === 0 ? "identical to wgpu-native's frame" :
      `largest channel difference ${max}/255; ${share.toFixed(2)}% of pixels differ by more than 1/255 ` +
      "(another WebGPU implementation: rasterisation and texture filtering may differ within the spec)";
  }

  api.ready = main().catch((e) => { fail("The page could not start WebGPU: " + e.message); throw e; });
})();
