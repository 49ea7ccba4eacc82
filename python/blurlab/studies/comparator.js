// blurlab's "look closer" comparator: each method beside the reference, in panels that move
// together. Written by blurlab.studies.comparator; Panzoom (vendor/panzoom) pans and zooms.
// Each .blurlab-look element gets `look` = {state(), setSplit(f), setError(on), setExposure(s)}
// and the page's comparators are in window.blurlabLooks (the browser tests read them).
(function () {
  "use strict";
  if (window.blurlabLooks) return; // the script is on the page more than once
  window.blurlabLooks = [];
  window.blurlabLookData = window.blurlabLookData || {};

  // sRGB encoding of [0, 1) linear values, as blurlab.io.linear_to_srgb, in 8 bits.
  const LUT_SIZE = 16384;
  const SRGB = new Uint8ClampedArray(LUT_SIZE + 1);
  for (let i = 0; i <= LUT_SIZE; i++) {
    const c = i / LUT_SIZE;
    const s = c <= 0.0031308 ? 12.92 * c : 1.055 * Math.pow(c, 1 / 2.4) - 0.055;
    SRGB[i] = Math.round(s * 255);
  }

  // A picture of 16-bit log2 codes (high bytes left, low bytes right; comparator.py's
  // _log_png) to linear RGB floats.
  async function decodeLog(base64, width, height, steps, offset) {
    const bytes = Uint8Array.from(atob(base64), (c) => c.charCodeAt(0));
    const bitmap = await createImageBitmap(new Blob([bytes], { type: "image/png" }), {
      colorSpaceConversion: "none",
      premultiplyAlpha: "none",
    });
    const canvas = document.createElement("canvas");
    canvas.width = 2 * width;
    canvas.height = height;
    const context = canvas.getContext("2d", { willReadFrequently: true });
    context.drawImage(bitmap, 0, 0);
    const pixels = context.getImageData(0, 0, 2 * width, height).data;
    const rgb = new Float32Array(width * height * 3);
    for (let y = 0; y < height; y++) {
      for (let x = 0; x < width; x++) {
        const high = 4 * (y * 2 * width + x);
        const low = high + 4 * width;
        for (let c = 0; c < 3; c++) {
          const code = 256 * pixels[high + c] + pixels[low + c];
          rgb[3 * (y * width + x) + c] = code && Math.pow(2, code / steps - offset);
        }
      }
    }
    return rgb;
  }

  // Reinhard's x / (1 + x) on x = exposure * rgb, then sRGB: blurlab.metrics.tone_map.
  function toneMapped(rgb, width, height, exposure) {
    const image = new ImageData(width, height);
    const out = image.data;
    for (let i = 0, o = 0; i < rgb.length; i += 3, o += 4) {
      for (let c = 0; c < 3; c++) {
        const x = Math.max(rgb[i + c], 0) * exposure;
        out[o + c] = SRGB[Math.round((x / (1 + x)) * LUT_SIZE)];
      }
      out[o + 3] = 255;
    }
    return image;
  }

  function setUp(root) {
    const width = Number(root.dataset.width);
    const views = [...root.querySelectorAll(".bl-look-view")];
    const stages = [...root.querySelectorAll(".bl-look-stage")];
    const tops = [...root.querySelectorAll(".bl-look-top")];
    const handles = [...root.querySelectorAll(".bl-look-handle")];
    const splitInput = root.querySelector(".bl-look-split");
    const errorInput = root.querySelector(".bl-look-error-toggle");
    const exposureInput = root.querySelector(".bl-look-exposure");
    const readout = root.querySelector(".bl-look-readout");
    const shownWidth = views[0].clientWidth;
    const maxPixel = Number(root.dataset.maxPixel); // screen px per image px at most
    const state = { split: 0.5, error: false, exposure: 0, ready: false };
    let transform = { x: 0, y: 0, scale: 1 };

    const pixelSize = () => (transform.scale * shownWidth) / width;
    // One Panzoom for all panels: it moves panel 0's reference and the transform is copied to
    // every stage, so that the panels cannot drift apart.
    const panzoom = Panzoom(stages[0], {
      noBind: true,
      minScale: 1,
      maxScale: (maxPixel * width) / shownWidth,
      step: 0.6,
      contain: "outside",
      setTransform: (element, value) => {
        transform = { x: value.x, y: value.y, scale: value.scale };
        const css = `scale(${value.scale}) translate(${value.x}px, ${value.y}px)`;
        for (const stage of stages) stage.style.transform = css;
        const px = pixelSize();
        readout.textContent = `1 image pixel = ${px < 10 ? px.toFixed(2) : px.toFixed(0)} screen px`;
      },
    });
    for (const view of views) {
      view.addEventListener("pointerdown", (event) => panzoom.handleDown(event));
      view.addEventListener(
        "wheel",
        (event) => {
          if (event.deltaY > 0 && panzoom.getScale() <= 1) return; // all out: the page scrolls
          // Panzoom measures from panel 0: the same point of the image there.
          const here = view.getBoundingClientRect();
          const first = views[0].getBoundingClientRect();
          panzoom.zoomWithWheel({
            deltaX: event.deltaX,
            deltaY: event.deltaY,
            clientX: event.clientX - here.left + first.left,
            clientY: event.clientY - here.top + first.top,
            preventDefault: () => event.preventDefault(),
          });
        },
        { passive: false },
      );
    }
    document.addEventListener("pointermove", (event) => panzoom.handleMove(event));
    for (const name of ["pointerup", "pointercancel"]) {
      document.addEventListener(name, (event) => panzoom.handleUp(event));
    }

    function setSplit(fraction) {
      state.split = Math.min(Math.max(Number(fraction), 0), 1);
      const percent = `${(100 * state.split).toFixed(3)}%`;
      for (const top of tops) top.style.clipPath = `inset(0 0 0 ${percent})`;
      for (const handle of handles) handle.style.left = percent;
      splitInput.value = state.split;
    }
    for (const handle of handles) {
      handle.addEventListener("pointerdown", (event) => {
        event.preventDefault();
        handle.setPointerCapture(event.pointerId);
        const view = handle.parentElement;
        const follow = (move) => {
          const box = view.getBoundingClientRect();
          setSplit((move.clientX - box.left) / box.width);
        };
        const stop = () => {
          handle.removeEventListener("pointermove", follow);
          handle.removeEventListener("pointerup", stop);
        };
        handle.addEventListener("pointermove", follow);
        handle.addEventListener("pointerup", stop);
      });
    }
    splitInput.addEventListener("input", () => setSplit(splitInput.value));

    function setError(on) {
      state.error = Boolean(on);
      root.classList.toggle("bl-look-showing-error", state.error);
      errorInput.checked = state.error;
    }
    errorInput.addEventListener("change", () => setError(errorInput.checked));

    // HDR: every canvas drawn from its linear data at the scene's exposure times 2^stops.
    const data = window.blurlabLookData[root.id];
    let linear = null;
    function draw() {
      if (!linear) return;
      const exposure = Number(root.dataset.exposure) * Math.pow(2, state.exposure);
      const height = Number(root.dataset.height);
      const pictures = {};
      for (const canvas of root.querySelectorAll("canvas[data-image]")) {
        const key = canvas.dataset.image;
        pictures[key] = pictures[key] || toneMapped(linear[key], width, height, exposure);
        canvas.getContext("2d").putImageData(pictures[key], 0, 0);
      }
    }
    function setExposure(stops) {
      state.exposure = Number(stops);
      if (exposureInput) {
        exposureInput.value = state.exposure;
        const sign = state.exposure >= 0 ? "+" : "";
        root.querySelector(".bl-look-stops").textContent = `${sign}${state.exposure} stops`;
      }
      draw();
    }
    if (exposureInput) {
      exposureInput.addEventListener("input", () => setExposure(exposureInput.value));
      const height = Number(root.dataset.height);
      const keys = Object.keys(data.images);
      Promise.all(keys.map((k) => decodeLog(data.images[k], width, height, data.steps, data.offset))).then(
        (decoded) => {
          linear = Object.fromEntries(keys.map((k, i) => [k, decoded[i]]));
          state.ready = true;
          draw();
        },
      );
    } else {
      state.ready = true;
    }
    root.querySelector(".bl-look-fit").addEventListener("click", () =>
      panzoom.reset({ animate: false }),
    );
    root.querySelector(".bl-look-in").addEventListener("click", () =>
      panzoom.zoomIn({ animate: false }),
    );
    root.querySelector(".bl-look-out").addEventListener("click", () =>
      panzoom.zoomOut({ animate: false }),
    );
    setSplit(0.5);

    root.look = {
      state: () => ({ ...state, ...transform, pixel: pixelSize(),
        transforms: stages.map((s) => s.style.transform) }),
      setSplit,
      setError,
      setExposure,
    };
    window.blurlabLooks.push(root);
  }

  function setUpAll() {
    for (const root of document.querySelectorAll(".blurlab-look")) {
      if (!root.look) setUp(root);
    }
  }
  if (document.readyState === "loading") {
    document.addEventListener("DOMContentLoaded", setUpAll);
  } else {
    setUpAll();
  }
})();
