// The material editor, generated from the registry (GET /api/materials, the table behind
// `gonio materials`): a row per parameter with its range and default — sliders for
// numbers, colour pickers for colours, nested editors for blend and layered parts.
// The material is a plain JSON object, edited in place; onChange() follows every edit.
"use strict";

const editor = (() => {
  let registry = { types: [], metals: [] };
  let dataFiles = [];

  const el = (tag, cls, text) => {
    const e = document.createElement(tag);
    if (cls) e.className = cls;
    if (text !== undefined) e.textContent = text;
    return e;
  };
  const spec = (type) => registry.types.find((t) => t.name === type);
  const example = (type) => JSON.parse(JSON.stringify((spec(type) || { example: { type } }).example));

  // Linear ↔ sRGB-encoded channel, for the colour picker (the material's colours are linear).
  const toSrgb = (c) => (c <= 0.0031308 ? 12.92 * c : 1.055 * Math.pow(c, 1 / 2.4) - 0.055);
  const toLinear = (s) => (s <= 0.04045 ? s / 12.92 : Math.pow((s + 0.055) / 1.055, 2.4));
  const hex = (rgb) =>
    "#" + rgb.map((c) => Math.round(255 * Math.min(1, Math.max(0, toSrgb(c)))).toString(16).padStart(2, "0")).join("");
  const fromHex = (h) => [1, 3, 5].map((i) => +toLinear(parseInt(h.slice(i, i + 2), 16) / 255).toFixed(4));

  // A slider's mapping for a range: linear, or logarithmic over a wide one (an index, an exponent).
  function scale(range) {
    let lo = range ? range.lo : 0, hi = range ? range.hi : 1;
    if (hi / Math.max(lo, 1e-3) > 1000) {
      lo = Math.max(lo, 1e-3); hi = Math.min(hi, 1e4);
      return { to: (t) => lo * Math.pow(hi / lo, t), from: (v) => Math.log(Math.max(v, lo) / lo) / Math.log(hi / lo) };
    }
    return { to: (t) => lo + (hi - lo) * t, from: (v) => (v - lo) / (hi - lo) };
  }
  // Inside the range: an open end is approached, never reached.
  function clampTo(range, v) {
    if (!range) return v;
    const eps = (range.hi - range.lo) * 1e-4;
    if (v <= range.lo) v = range.lo_open ? range.lo + eps : range.lo;
    if (v >= range.hi) v = range.hi_open ? range.hi - eps : range.hi;
    return +v.toPrecision(6);
  }

  function numberControl(range, value, set) {
    const box = el("span", "value");
    const num = el("input");
    num.type = "number"; num.step = "any"; num.value = value;
    box.append(num);
    let slider = null;
    if (range) {
      const s = scale(range);
      slider = el("input");
      slider.type = "range"; slider.min = 0; slider.max = 1000; slider.step = 1;
      slider.value = Math.round(1000 * s.from(value));
      slider.addEventListener("input", () => {
        const v = clampTo(range, s.to(slider.value / 1000));
        num.value = v;
        set(v);
      });
      box.prepend(slider);
    }
    num.addEventListener("input", () => {
      const v = parseFloat(num.value);
      if (!Number.isFinite(v)) return;
      if (slider) slider.value = Math.round(1000 * scale(range).from(v));
      set(v);  // out of range: the server's message says so
    });
    return box;
  }

  function colourControl(p, value, set) {
    const box = el("span", "value");
    if (typeof value === "object" && !Array.isArray(value)) {
      box.append(el("span", "", "spectrum: edit it in the JSON"));
      return box;
    }
    const rgb = Array.isArray(value) ? value.slice() : [value, value, value];
    const reflectanceLike = !p.range || p.range.hi <= 1;
    const nums = [0, 1, 2].map((i) => {
      const n = el("input");
      n.type = "number"; n.step = "any"; n.value = rgb[i]; n.title = "RGB"[i] + " (linear)";
      n.addEventListener("input", () => {
        const v = parseFloat(n.value);
        if (!Number.isFinite(v)) return;
        rgb[i] = v;
        if (picker) picker.value = hex(rgb);
        set(rgb.slice());
      });
      return n;
    });
    let picker = null;
    if (reflectanceLike) {
      picker = el("input");
      picker.type = "color"; picker.value = hex(rgb);
      picker.addEventListener("input", () => {
        const c = fromHex(picker.value);
        c.forEach((v, i) => { rgb[i] = v; nums[i].value = v; });
        set(rgb.slice());
      });
      box.append(picker);
    }
    box.append(...nums);
    return box;
  }

  function roughnessControl(p, value, set) {
    const box = el("span", "value");
    const a = Array.isArray(value) ? value.slice() : [value, value];
    const aniso = el("input");
    aniso.type = "checkbox"; aniso.checked = Array.isArray(value); aniso.title = "anisotropic: [alpha_x, alpha_y]";
    const emit = () => set(aniso.checked ? a.slice() : a[0]);
    const ax = numberControl(p.range, a[0], (v) => { a[0] = v; emit(); });
    const ay = numberControl(p.range, a[1], (v) => { a[1] = v; emit(); });
    ay.style.display = aniso.checked ? "" : "none";
    aniso.addEventListener("change", () => { ay.style.display = aniso.checked ? "" : "none"; emit(); });
    const label = el("label", "inline");
    label.append(aniso, "aniso");
    box.append(ax, label, ay);
    return box;
  }

  function choiceControl(choices, value, set) {
    const s = el("select");
    for (const c of choices) {
      const o = el("option", "", c);
      o.value = c;
      s.append(o);
    }
    if (!choices.includes(value)) {
      const o = el("option", "", String(value));
      o.value = value;
      s.append(o);
    }
    s.value = value;
    s.addEventListener("change", () => set(s.value));
    return s;
  }

  function initial(p) {
    if (p.default !== null) return JSON.parse(JSON.stringify(p.default));
    switch (p.kind) {
      case "number": return p.range ? clampTo(p.range, scale(p.range).to(0.5)) : 1;
      case "colour": return 0.5;
      case "roughness": return 0.2;
      case "choice": return p.choices[0];
      case "boolean": return false;
      case "metal": return p.choices[0];
      case "materials": return [example("diffuse"), example("roughconductor")];
      case "material": return example(p.name === "top" ? "roughdielectric" : "diffuse");
      case "file": return dataFiles[0] || "material.binary";
      case "film": return { thickness: 300, eta: 1.33 };
    }
    return 0;
  }

  function control(p, m, onChange, depth) {
    const set = (v) => { m[p.name] = v; onChange(); };
    const v = m[p.name];
    switch (p.kind) {
      case "number": return typeof v === "number" ? numberControl(p.range, v, set) : el("span", "", "edit it in the JSON");
      case "colour": return colourControl(p, v, set);
      case "roughness": return roughnessControl(p, v, set);
      case "choice": case "metal": return choiceControl(p.choices || [], v, set);
      case "boolean": {
        const c = el("input");
        c.type = "checkbox"; c.checked = !!v;
        c.addEventListener("change", () => set(c.checked));
        return c;
      }
      case "file": return choiceControl(dataFiles.length ? dataFiles : [v], v, set);
      case "film": {
        const box = el("span", "value");
        box.append("nm", numberControl({ lo: 0, hi: 2000, lo_open: false, hi_open: false }, v.thickness, (x) => { v.thickness = x; onChange(); }));
        box.append("η", numberControl({ lo: 1, hi: 3, lo_open: false, hi_open: false }, v.eta, (x) => { v.eta = x; onChange(); }));
        return box;
      }
      case "material": {
        const box = el("div", "nested");
        build(box, v, onChange, depth + 1);
        return box;
      }
      case "materials": {
        const box = el("div");
        v.forEach((part) => {
          const n = el("div", "nested");
          build(n, part, onChange, depth + 1);
          box.append(n);
        });
        return box;
      }
    }
    return el("span", "", JSON.stringify(v));
  }

  function paramRow(p, m, onChange, depth, rebuild) {
    const present = p.name in m;
    const nested = present && (p.kind === "material" || p.kind === "materials");
    const row = el("div", "param" + (present ? "" : " absent"));
    const name = el("span", "name", p.name);
    name.title = p.meaning + (p.range ? " Range " + p.range.text + "." : "") +
      (p.default !== null ? " Default " + JSON.stringify(p.default) + "." : p.required ? " Required." : "");
    row.append(name);
    if (!present) {
      row.append(el("span", "", p.default !== null ? "default " + JSON.stringify(p.default) : p.required ? "required" : "not set"));
      const add = el("button", "", "+");
      add.title = "set " + p.name;
      add.addEventListener("click", () => { m[p.name] = initial(p); rebuild(); onChange(); });
      row.append(add);
      return [row];
    }
    const c = control(p, m, onChange, depth);
    if (nested) {
      row.append(el("span"), el("span"));
      return [row, c];
    }
    row.append(c);
    if (!p.required) {
      const remove = el("button", "", "×");
      remove.title = "remove " + p.name + " (use the default)";
      remove.addEventListener("click", () => { delete m[p.name]; rebuild(); onChange(); });
      row.append(remove);
    } else {
      row.append(el("span"));
    }
    return [row];
  }

  // The editor of material `m` (an object, edited in place) in `root`.
  function build(root, m, onChange, depth = 0) {
    root.textContent = "";
    const rebuild = () => build(root, m, onChange, depth);
    const head = el("div", "param");
    head.append(el("span", "name", "type"));
    const select = choiceControl(registry.types.map((t) => t.name), m.type, (t) => {
      for (const k of Object.keys(m)) delete m[k];
      Object.assign(m, example(t));
      rebuild();
      onChange();
    });
    head.append(select, el("span"));
    root.append(head);
    const s = spec(m.type);
    if (!s) return;
    const summary = el("div", "readout", s.summary);
    summary.title = s.source;
    root.append(summary);
    for (const p of s.params) root.append(...paramRow(p, m, onChange, depth, rebuild));
  }

  return {
    setRegistry: (r) => { registry = r; },
    setDataFiles: (f) => { dataFiles = f; },
    example,
    build,
  };
})();
