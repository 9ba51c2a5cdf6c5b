/* aaeval comparison viewer: written into the report page by aaeval.report.viewer.
 *
 * Hand-written because no plotting library shipped in a Python package flips images by
 * key with linked nearest-neighbour zoom. Data come from <script> files that call
 * AAV.add(group, payload) (script tags load from file://, fetch() would not); images are
 * zlib-compressed little-endian float16 arrays (FLIP maps: bytes) in base64, inflated with the browser's
 * DecompressionStream. Nothing is fetched from the network.
 *
 * Keys (over a viewer, or after clicking it): 0-9 show panel N (0 = ground truth) in the
 * A/B view; f or space flips between the last two; n / p next / previous panel;
 * [ / ] previous / next frame; k play; m next display mode; + / - exposure; s space-time
 * slice; z reset zoom. Wheel zooms about the cursor, dragging pans; all panels follow.
 */
(function () {
  "use strict";
  const AAV = (window.AAV = window.AAV || {});
  AAV.data = AAV.data || {};
  AAV.viewers = [];
  AAV.errors = [];
  AAV.add = function (group, payload) { AAV.data[group] = payload; };
  const LUTS = /*LUTS*/ {};

  const HALF = (function () {
    const t = new Float32Array(65536);
    for (let h = 0; h < 65536; h++) {
      const s = h & 0x8000 ? -1 : 1, e = (h >> 10) & 31, f = h & 1023;
      t[h] = s * (e === 0 ? f * Math.pow(2, -24) : e === 31 ? (f ? NaN : Infinity) : (1 + f / 1024) * Math.pow(2, e - 15));
    }
    return t;
  })();
  const SRGB = (function () {  // linear [0, 1] in 4096 steps -> 8-bit sRGB
    const t = new Uint8ClampedArray(4097);
    for (let i = 0; i <= 4096; i++) {
      const x = i / 4096;
      t[i] = Math.round(255 * (x <= 0.0031308 ? 12.92 * x : 1.055 * Math.pow(x, 1 / 2.4) - 0.055));
    }
    return t;
  })();

  async function inflate(b64) {
    const bin = atob(b64), bytes = new Uint8Array(bin.length);
    for (let i = 0; i < bin.length; i++) bytes[i] = bin.charCodeAt(i);
    const stream = new Blob([bytes]).stream().pipeThrough(new DecompressionStream("deflate"));
    return new Response(stream).arrayBuffer();
  }

  async function decode(b64) {  // float16 array
    const half = new Uint16Array(await inflate(b64)), out = new Float32Array(half.length);
    for (let i = 0; i < half.length; i++) out[i] = HALF[half[i]];
    return out;
  }

  async function decode8(b64) {  // bytes meaning [0, 1] in steps of 1/255
    const codes = new Uint8Array(await inflate(b64)), out = new Float32Array(codes.length);
    for (let i = 0; i < codes.length; i++) out[i] = codes[i] / 255;
    return out;
  }

  function el(tag, attrs, parent) {
    const e = document.createElement(tag);
    for (const k in attrs || {}) {
      if (k === "text") e.textContent = attrs[k]; else e.setAttribute(k, attrs[k]);
    }
    if (parent) parent.appendChild(e);
    return e;
  }

  function fmt(v) {
    if (!isFinite(v)) return String(v);
    const a = Math.abs(v);
    return a !== 0 && (a < 1e-3 || a >= 1e4) ? v.toExponential(2) : v.toFixed(4);
  }

  const MODES = ["image", "abs", "signed", "flip"];
  const MODE_NAMES = { image: "image", abs: "|error|", signed: "signed error", flip: "FLIP map" };

  class Viewer {
    constructor(root, payload) {
      this.root = root;
      this.payload = payload;
      this.scene = 0; this.frame = 0; this.mode = "image"; this.ev = 0; this.shared = true;
      this.layout = "grid"; this.slice = false; this.shown = 0; this.previous = 1;
      this.zoom = 1; this.cx = null; this.cy = null; this.timer = null; this.row = null;
      root.tabIndex = 0;
      // keys act on the viewer under the pointer or holding the focus, never on the page
      root.addEventListener("mouseenter", () => { AAV.hover = this; });
      root.addEventListener("mouseleave", () => { if (AAV.hover === this) AAV.hover = null; });
      this.build();
    }

    get sc() { return this.payload.scenes[this.scene]; }

    async load(scene) {
      if (scene.decoded) return;
      for (const p of scene.panels) {
        p.pixels = await decode(p.img);
        p.err = p.error ? await decode(p.error) : null;
        p.flipmap = p.flip ? await decode8(p.flip) : null;
        p.maxErr = 0; p.maxFlip = 0;
        if (p.err) for (let i = 0; i < p.err.length; i++) p.maxErr = Math.max(p.maxErr, Math.abs(p.err[i]));
        if (p.flipmap) for (let i = 0; i < p.flipmap.length; i++) p.maxFlip = Math.max(p.maxFlip, p.flipmap[i]);
      }
      scene.sharedErr = Math.max(...scene.panels.map((p) => p.maxErr));
      scene.sharedFlip = Math.max(...scene.panels.map((p) => p.maxFlip));
      scene.decoded = true;
    }

    build() {
      this.root.textContent = "";
      const r = this.root, bar = el("div", { class: "aav-bar" }, r);
      const sel = el("select", { "aria-label": "scene", class: "aav-scene" }, bar);
      this.payload.scenes.forEach((s, i) => el("option", { value: i, text: s.name }, sel));
      sel.onchange = () => this.setScene(+sel.value);
      this.frameLabel = el("span", { class: "aav-framelabel" }, bar);
      this.slider = el("input", { type: "range", min: 0, value: 0, step: 1, "aria-label": "frame" }, bar);
      this.slider.oninput = () => this.setFrame(+this.slider.value);
      this.playBtn = el("button", { type: "button", text: "play" }, bar);
      this.playBtn.onclick = () => this.play();
      const mode = el("select", { "aria-label": "display", class: "aav-mode" }, bar);
      MODES.forEach((m) => el("option", { value: m, text: MODE_NAMES[m] }, mode));
      mode.onchange = () => { this.mode = mode.value; this.redraw(); };
      this.modeSel = mode;
      const scale = el("select", { "aria-label": "error scale" }, bar);
      el("option", { value: "shared", text: "shared scale" }, scale);
      el("option", { value: "own", text: "each panel's own scale" }, scale);
      scale.value = this.shared ? "shared" : "own";
      scale.onchange = () => { this.shared = scale.value === "shared"; this.redraw(); };
      const lay = el("select", { "aria-label": "layout", class: "aav-layout" }, bar);
      [["grid", "side by side"], ["ab", "A/B (keys)"]].forEach(([v, t]) => el("option", { value: v, text: t }, lay));
      lay.onchange = () => this.setLayout(lay.value);
      this.layoutSel = lay;
      const sl = el("label", { text: " space-time " }, bar);
      this.sliceBox = el("input", { type: "checkbox", "aria-label": "space-time slice" }, sl);
      this.sliceBox.onchange = () => { this.slice = this.sliceBox.checked; this.fit(); this.redraw(); };
      el("span", { text: " exposure " }, bar);
      this.evInput = el("input", { type: "range", min: -8, max: 8, step: 0.5, value: 0, "aria-label": "exposure" }, bar);
      this.evInput.oninput = () => { this.ev = +this.evInput.value; this.redraw(); };
      this.evLabel = el("span", {}, bar);
      const reset = el("button", { type: "button", text: "reset zoom" }, bar);
      reset.onclick = () => { this.fit(); this.redraw(); };
      this.readout = el("div", { class: "aav-readout", text: "move the cursor over an image for its linear values" }, r);
      this.stage = el("div", { class: "aav-stage" }, r);
      el("div", { class: "aav-help", text: "keys (pointer over the viewer, or focus in it): 0-9 panel, n/p or arrows next/previous (every panel), Tab a panel and Enter to show it, f/space flip A/B, [ ] frame, k play, m mode, +/- exposure, s space-time slice, z reset zoom; wheel zooms, drag pans" }, r);
      this.setScene(0);
    }

    async setScene(i) {
      this.scene = i;
      this.root.dataset.ready = "0";
      await this.load(this.sc);
      this.slider.max = this.sc.frames - 1;
      this.frame = Math.min(this.frame, this.sc.frames - 1);
      this.row = this.sc.row;
      this.shown = Math.min(this.shown, this.sc.panels.length - 1);
      this.makePanels();
      this.fit();
      this.redraw();
      this.root.dataset.ready = "1";
    }

    setLayout(v) { this.layout = v; this.layoutSel.value = v; this.makePanels(); this.fit(); this.redraw(); }

    makePanels() {
      this.stage.textContent = "";
      this.canvases = [];
      const sc = this.sc, ab = this.layout === "ab";
      const list = ab ? [this.shown] : sc.panels.map((_, i) => i);
      const side = ab ? 560 : Math.max(150, Math.min(260, Math.floor(1100 / Math.min(5, list.length))));
      for (const idx of list) {
        const box = el("div", { class: "aav-panel" }, this.stage);
        const cap = el("div", { class: "aav-cap" }, box);
        cap.style.width = side + "px";
        const c = el("canvas", { width: side, height: side }, box);
        const info = el("div", { class: "aav-info" }, box);
        c.dataset.panel = idx;
        c.tabIndex = 0;  // Tab reaches every panel; Enter shows it alone
        c.setAttribute("role", "img");
        c.addEventListener("keydown", (ev) => {
          if (ev.key === "Enter" && this.layout !== "ab") { this.show(idx); ev.preventDefault(); ev.stopPropagation(); }
        });
        this.canvases.push({ canvas: c, cap, info, idx, off: document.createElement("canvas") });
        this.attach(c);
      }
    }

    attach(c) {
      let drag = null;
      c.addEventListener("wheel", (ev) => {
        ev.preventDefault();
        const [ix, iy] = this.toImage(c, ev.offsetX, ev.offsetY, false);
        const f = ev.deltaY < 0 ? 1.25 : 0.8;
        const s0 = this.scaleFor(c), s1 = s0 * f;
        this.zoom *= f;
        // keep the image point under the cursor where it is
        this.cx = ix - (ev.offsetX - c.width / 2) / s1;
        this.cy = iy - (ev.offsetY - c.height / 2) / s1;
        this.redraw();
      }, { passive: false });
      c.addEventListener("mousedown", (ev) => { drag = [ev.offsetX, ev.offsetY]; });
      window.addEventListener("mouseup", () => { drag = null; });
      c.addEventListener("mousemove", (ev) => {
        if (drag) {
          const s = this.scaleFor(c);
          this.cx -= (ev.offsetX - drag[0]) / s;
          this.cy -= (ev.offsetY - drag[1]) / s;
          drag = [ev.offsetX, ev.offsetY];
          this.redraw();
        }
        this.read(c, ev.offsetX, ev.offsetY);
      });
    }

    // rows per frame in the space-time slice: short animations still fill a squarish panel
    get rep() { const sc = this.sc; return Math.max(1, Math.round(sc.width / sc.frames / 1.5)); }
    dims() { const sc = this.sc; return this.slice ? [sc.width, sc.frames * this.rep] : [sc.width, sc.height]; }
    fit() { const [w, h] = this.dims(); this.zoom = 1; this.cx = w / 2; this.cy = h / 2; }
    scaleFor(c) { const [w, h] = this.dims(); return Math.min(c.width / w, c.height / h) * this.zoom; }
    toImage(c, x, y, floor = true) {
      const s = this.scaleFor(c);
      const ix = (x - c.width / 2) / s + this.cx, iy = (y - c.height / 2) / s + this.cy;
      return floor ? [Math.floor(ix), Math.floor(iy)] : [ix, iy];
    }

    setFrame(k) {
      this.frame = ((k % this.sc.frames) + this.sc.frames) % this.sc.frames;
      this.redraw();
    }

    play() {
      if (this.timer) { clearInterval(this.timer); this.timer = null; this.playBtn.textContent = "play"; return; }
      this.timer = setInterval(() => this.setFrame(this.frame + 1), 250);
      this.playBtn.textContent = "stop";
    }

    show(idx) {
      const n = this.sc.panels.length;
      idx = ((idx % n) + n) % n;
      if (idx !== this.shown) { this.previous = this.shown; this.shown = idx; }
      if (this.layout !== "ab") this.setLayout("ab"); else { this.makePanels(); this.redraw(); }
    }

    key(ev) {
      const k = ev.key;
      if (/^[0-9]$/.test(k)) this.show(+k);
      else if (k === "f" || k === " ") this.show(this.previous);
      else if (k === "n" || k === "ArrowRight") this.show(this.shown + 1);
      else if (k === "p" || k === "ArrowLeft") this.show(this.shown - 1);
      else if (k === "]") this.setFrame(this.frame + 1);
      else if (k === "[") this.setFrame(this.frame - 1);
      else if (k === "k") this.play();
      else if (k === "m") { this.mode = MODES[(MODES.indexOf(this.mode) + 1) % MODES.length]; this.modeSel.value = this.mode; this.redraw(); }
      else if (k === "+" || k === "=") { this.ev = Math.min(8, this.ev + 0.5); this.evInput.value = this.ev; this.redraw(); }
      else if (k === "-") { this.ev = Math.max(-8, this.ev - 0.5); this.evInput.value = this.ev; this.redraw(); }
      else if (k === "s") { this.slice = !this.slice; this.sliceBox.checked = this.slice; this.fit(); this.redraw(); }
      else if (k === "z") { this.fit(); this.redraw(); }
      else return false;
      return true;
    }

    // value of panel p at image pixel (x, y) of frame f: [r, g, b] or a scalar map
    pixel(p, f, x, y) {
      const sc = this.sc, i = (f * sc.height + y) * sc.width + x;
      return [p.pixels[3 * i], p.pixels[3 * i + 1], p.pixels[3 * i + 2]];
    }

    scaleOf(p) {
      const sc = this.sc;
      if (this.mode === "flip") return this.shared ? sc.sharedFlip : p.maxFlip;
      return this.shared ? sc.sharedErr : p.maxErr;
    }

    paint(entry) {
      const sc = this.sc, p = sc.panels[entry.idx], [w, h] = this.dims();
      const off = entry.off; off.width = w; off.height = h;
      const ctx = off.getContext("2d"), img = ctx.createImageData(w, h), d = img.data;
      const gain = Math.pow(2, this.ev), mode = p.err || this.mode === "image" ? this.mode : "image";
      const scale = this.scaleOf(p) || 1e-30, row = Math.max(0, Math.min(sc.height - 1, this.row));
      const mag = LUTS.magma, rdbu = LUTS.rdbu, rep = this.rep;
      for (let yy = 0; yy < h; yy++) {
        const f = this.slice ? Math.floor(yy / rep) : this.frame, y = this.slice ? row : yy;
        for (let x = 0; x < w; x++) {
          const i = (f * sc.height + y) * sc.width + x, o = 4 * (yy * w + x);
          if (mode === "image") {
            for (let c = 0; c < 3; c++) d[o + c] = SRGB[Math.max(0, Math.min(4096, Math.round(p.pixels[3 * i + c] * gain * 4096)))];
          } else {
            let rgb;
            if (mode === "abs") rgb = mag[Math.min(255, Math.round(255 * Math.abs(p.err[i]) / scale))];
            else if (mode === "signed") rgb = rdbu[Math.max(0, Math.min(255, Math.round(127.5 + 127.5 * p.err[i] / scale)))];
            else rgb = mag[Math.min(255, Math.round(255 * (p.flipmap ? p.flipmap[i] : 0) / scale))];
            d[o] = rgb[0]; d[o + 1] = rgb[1]; d[o + 2] = rgb[2];
          }
          d[o + 3] = 255;
        }
      }
      ctx.putImageData(img, 0, 0);
      const c = entry.canvas, g = c.getContext("2d"), s = this.scaleFor(c);
      g.fillStyle = "#777"; g.fillRect(0, 0, c.width, c.height);
      g.imageSmoothingEnabled = false;
      g.drawImage(off, c.width / 2 - this.cx * s, c.height / 2 - this.cy * s, w * s, h * s);
      const other = sc.panels[this.previous] ? `[${this.previous}] ${sc.panels[this.previous].label}` : "";
      const ab = this.layout === "ab" ? ` [${entry.idx}] (f flips to ${other})` : ` [${entry.idx}]`;
      entry.cap.textContent = p.label + ab;
      entry.cap.title = p.label;  // the full label on hover; the caption wraps as well
      entry.canvas.setAttribute("aria-label", `panel ${entry.idx}: ${p.label}`);
      entry.cap.style.borderLeft = `6px solid ${p.colour}`;
      const parts = [mode === "image" ? (p.err ? "" : "ground truth")
        : `${MODE_NAMES[mode]}, ${this.shared ? "shared" : "own"} scale ${mode === "signed" ? "±" : "0.."}${fmt(scale)}`];
      if (this.slice) parts.push(`space-time: row ${row}, x column, y frame 1-${sc.frames} (down)`);
      entry.info.textContent = parts.filter((t) => t).join(" · ");
    }

    redraw() {
      const sc = this.sc;
      this.slider.value = this.frame;
      this.frameLabel.textContent = ` frame ${this.frame + 1}/${sc.frames} `;
      this.evLabel.textContent = ` ${this.ev >= 0 ? "+" : ""}${this.ev} EV `;
      for (const e of this.canvases) this.paint(e);
      this.root.dataset.shown = this.sc.panels[this.shown].label;
      this.root.dataset.zoom = this.zoom.toFixed(3);
      this.root.dataset.layout = this.layout;
      this.root.dataset.slice = this.slice ? "1" : "0";
    }

    read(c, x, y) {
      const sc = this.sc, [ix, iy] = this.toImage(c, x, y);
      const [w, h] = this.dims();
      if (ix < 0 || iy < 0 || ix >= w || iy >= h) return;
      const f = this.slice ? Math.floor(iy / this.rep) : this.frame, yy = this.slice ? this.row : iy;
      if (!this.slice) this.row = iy;
      const p = sc.panels[+c.dataset.panel], gt = sc.panels[0];
      const v = this.pixel(p, f, ix, yy), g = this.pixel(gt, f, ix, yy);
      const i = (f * sc.height + yy) * sc.width + ix;
      let text = `pixel (x ${ix}, y ${yy}, frame ${f + 1}) linear RGB: ${p.label} ${v.map(fmt).join(" ")}`;
      if (p !== gt) text += ` | ground truth ${g.map(fmt).join(" ")} | error (mean over RGB) ${fmt(p.err[i])}`
        + (p.flipmap ? ` | FLIP ${fmt(p.flipmap[i])}` : "");
      this.readout.textContent = text;
    }
  }

  // The viewer a key is for: the one holding the focus, else the one under the pointer;
  // none (the key does what it does on the page: Space and arrows scroll) otherwise.
  AAV.target = function (ev) {
    const t = ev.target && ev.target.tagName;
    if (t === "INPUT" && ev.target.type !== "range" && ev.target.type !== "checkbox") return null;
    if (t === "SELECT" || t === "TEXTAREA" || ev.ctrlKey || ev.metaKey || ev.altKey) return null;
    const focused = document.activeElement && document.activeElement.closest
      ? document.activeElement.closest(".aav") : null;
    if (focused) return AAV.viewers.find((v) => v.root === focused) || null;
    return AAV.hover || null;
  };

  document.addEventListener("keydown", (ev) => {
    const v = AAV.target(ev);
    if (v && v.key(ev)) ev.preventDefault();
  });

  AAV.init = function () {
    for (const root of document.querySelectorAll(".aav[data-group]")) {
      const payload = AAV.data[root.dataset.group];
      if (!payload) { root.textContent = "viewer data missing: " + root.dataset.group; continue; }
      AAV.viewers.push(new Viewer(root, payload));
    }
  };
})();
