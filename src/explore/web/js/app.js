// The page: the state (material, angles, wavelength) kept in the URL hash, and every view
// redrawn from the server's answers when it changes.
"use strict";

// Errors the page meets are listed in #errors (hidden), where the browser test reads them.
window.addEventListener("error", (e) => reportError(e.message));
window.addEventListener("unhandledrejection", (e) => reportError(String(e.reason)));
function reportError(text) {
  const list = document.getElementById("errors");
  if (list) list.textContent += text + "\n";
}

// The time from an input (a slider moved, a field typed in) to the end of the redraw of
// every 2D view that input changes (issue 36: within 100 ms), measured here, in the page:
// the input event's time stamp, then each view's draw after it. A view announces the
// request it starts (expect) and its draw or its message (done); when none is pending the
// input's record is complete. An input that a newer one overtakes before its views are
// drawn is counted as superseded (its requests were aborted). window.gonioLatency holds the
// records; #latency (hidden) their JSON, for tests and scripts/explore_latency.mjs.
const latency = (() => {
  const records = [];
  let current = null, superseded = 0;
  function publish() {
    const out = document.getElementById("latency");
    if (out) out.textContent = JSON.stringify({ records, superseded });
  }
  document.addEventListener("input", (e) => {
    if (current && !current.complete && current.expected > 0) ++superseded;
    const t0 = e.timeStamp > 0 ? e.timeStamp : performance.now();
    current = { t0, source: e.target.id || e.target.type, pending: new Set(), expected: 0,
                views: {}, complete: false };
  }, true);
  return {
    records,
    // The token ties a view's draw to the input it answers (null: no input is measured).
    expect(view) {
      if (!current || current.complete) return null;
      current.pending.add(view);
      ++current.expected;
      return current;
    },
    done(token, view) {
      if (!token || token !== current || token.complete || !token.pending.has(view)) return;
      token.pending.delete(view);
      token.views[view] = +(performance.now() - token.t0).toFixed(1);
      if (token.pending.size) return;
      token.complete = true;
      records.push({ source: token.source, total: Math.max(...Object.values(token.views)), views: token.views });
      publish();
    },
    // The sphere's first image after the input (issue 36: within 300 ms), not a 2D view.
    sphere(token) {
      if (!token || token.sphere !== undefined) return;
      token.sphere = +(performance.now() - token.t0).toFixed(1);
      const r = records.find((x) => x.views === token.views);
      if (r) { r.sphere = token.sphere; publish(); }
    },
    current: () => current,
    summary: () => ({ records, superseded }),
  };
})();
window.gonioLatency = latency;

(() => {
  const $ = (id) => document.getElementById(id);
  // Each view marks itself drawn (data-drawn on its canvas), for the browser test.
  const drawn = (id) => { $(id).dataset.drawn = String(+($(id).dataset.drawn || 0) + 1); };
  const state = { material: null, theta_i: 30, phi_d: 90, spectral: false, wavelength: 550, lobe: "f_cos", eta: 1.5,
                  light_x: 0.5, light_y: 0.5, environment: 0.1, environment_map: "uniform", exposure: 0, sphere_passes: 64,
                  compare: false, material_b: null, yaw: -0.6, pitch: 0.35 };
  let lobe3dData = null;
  let bValid = false;
  let sliceData = null, slicePanel = null, timer = null;

  function status(text, kind) {
    const s = $("status");
    s.textContent = text;
    s.className = "status " + (kind || "");
  }

  // The request body every view shares: the material and, in spectral mode, the wavelength.
  function body(extra, spectral = true, material = state.material) {
    const b = Object.assign({ bsdf: material }, extra);
    if (spectral && state.spectral) b.wavelength = state.wavelength;
    return b;
  }

  function saveHash() {
    history.replaceState(null, "", "#" + encodeURIComponent(JSON.stringify(state)));
  }
  function loadHash() {
    if (location.hash.length < 2) return false;
    try {
      const s = JSON.parse(decodeURIComponent(location.hash.slice(1)));
      if (!s || typeof s.material !== "object" || s.material === null) return false;
      Object.assign(state, s);
      return true;
    } catch (e) {
      return false;
    }
  }

  function syncControls() {
    $("theta-i").value = state.theta_i; $("theta-i-out").textContent = state.theta_i + "°";
    $("phi-d").value = state.phi_d; $("phi-d-out").textContent = state.phi_d + "°";
    $("spectral").checked = state.spectral;
    $("wavelength").value = state.wavelength; $("wavelength-out").textContent = state.wavelength + " nm";
    $("wavelength").disabled = !state.spectral;
    $("fresnel-eta").value = state.eta;
    $("exposure").value = state.exposure;
    $("environment").value = state.environment;
    $("environment-map").value = state.environment_map;
    for (const r of document.querySelectorAll("input[name=lobe-mode]")) r.checked = r.value === state.lobe;
  }

  function buildEditor() {
    editor.build($("editor"), state.material, onMaterialEdited);
    $("compare").checked = state.compare;
    $("compare-panel").hidden = !state.compare;
    if (state.compare) {
      if (!state.material_b) state.material_b = editor.example("diffuse");
      editor.build($("editor-b"), state.material_b, schedule);
    }
  }
  function onMaterialEdited() {
    $("json").value = JSON.stringify(state.material, null, 2);
    schedule();
  }
  function schedule() {
    saveHash();
    clearTimeout(timer);
    // The next task: input events of one task make one update, and a newer input aborts
    // the older requests anyway (api.js); a longer pause would count in the latency.
    timer = setTimeout(update, 0);
  }

  const shown = (e, canvas) => {
    if (api.isAbort(e)) return;
    plot.message($(canvas), e.message);
  };

  // Material B, when comparing: valid or not, in its own status line.
  async function validateB() {
    bValid = false;
    if (!state.compare) return;
    const s = $("status-b");
    try {
      const v = await api.post("/api/validate", body({}, false, state.material_b), "validate_b");
      s.textContent = "B valid: " + v.name;
      s.className = "status ok";
      bValid = true;
    } catch (e) {
      if (api.isAbort(e)) return;
      s.textContent = "B: " + e.message;
      s.className = "status error";
    }
  }
  const comparing = () => state.compare && bValid;

  // A's validation runs beside the views (each view of a bad material shows the same
  // message): a round trip less between a slider and the plots. B's comes first, as the
  // views ask whether to compare.
  async function update() {
    api.post("/api/validate", body({}, false), "validate").then((v) => status("valid: " + v.name, "ok"),
      (e) => { if (!api.isAbort(e)) status(e.message, "error"); });
    await validateB();
    // The sphere starts once the 2D views are drawn: on two cores its passes would
    // otherwise take the CPU the views need to follow a slider within 100 ms.
    const sphereToken = latency.current();
    await Promise.all([updateLobe(), updateLobe3d(), updateSlice(), updateAlbedo(), updateFresnel()]);
    updateSphere(sphereToken);
    probeInput();
  }
  // state.probe_input = {id, value}: once the views are drawn, that control takes the
  // value and fires its input event, as a slider's move does (the browser test's input,
  // without a driver: the latency recorder then measures it).
  let probedInput = false;
  function probeInput() {
    if (!state.probe_input || probedInput) return;
    probedInput = true;
    const el = $(state.probe_input.id);
    if (!el) return;
    el.value = state.probe_input.value;
    el.dispatchEvent(new Event("input", { bubbles: true }));
  }

  async function updateLobe3d() {
    const token = latency.expect("lobe3d");
    try {
      lobe3dData = await api.post("/api/lobe3d", body({ theta_i: state.theta_i, count_theta: 24, count_phi: 48 }), "lobe3d");
      drawLobe3d();
      drawn("lobe3d");
    } catch (e) { shown(e, "lobe3d"); } finally { latency.done(token, "lobe3d"); }
  }
  function drawLobe3d() {
    if (lobe3dData) plot.lobe3d($("lobe3d"), lobe3dData, lobe3dData[state.lobe], state.yaw, state.pitch);
  }
  let turning = null;
  function turnLobe3d(ev) {
    if (!(ev.buttons & 1)) { turning = null; return; }
    if (turning) {
      state.yaw += (ev.clientX - turning.x) * 0.01;
      state.pitch = Math.max(-1.5, Math.min(1.5, state.pitch + (ev.clientY - turning.y) * 0.01));
      drawLobe3d();
      saveHash();
    }
    turning = { x: ev.clientX, y: ev.clientY };
  }

  // The sphere: passes of gonio's renderer with successive seeds, averaged here (1 sample
  // per pixel first, then 4 per pass, up to 256), restarted when anything changes.
  const SPHERE_SIZE = 128;
  // A and, when comparing, B side by side, each its own run of passes.
  const spheres = { a: { run: 0, acc: null, samples: 0, canvas: "sphere", key: "sphere" },
                    b: { run: 0, acc: null, samples: 0, canvas: "sphere-b", key: "sphere_b" } };
  function updateSphere(token = null) {
    const both = comparing();
    $("sphere-b").hidden = !both;
    runSphere(spheres.a, state.material, token);
    if (both) runSphere(spheres.b, state.material_b, null);
    else ++spheres.b.run;  // stops B's passes
  }
  async function runSphere(sp, material, token) {
    const run = ++sp.run;
    sp.acc = new Float32Array(SPHERE_SIZE * SPHERE_SIZE * 3);
    sp.samples = 0;
    for (let pass = 0; pass < state.sphere_passes && run === sp.run; ++pass) {
      const spp = pass === 0 ? 1 : 4;
      let d;
      try {
        d = await api.post("/api/sphere", body({ size: SPHERE_SIZE, spp, seed: pass, light_x: state.light_x,
          light_y: state.light_y, environment: state.environment, environment_map: state.environment_map,
          spectral: state.spectral }, false, material), sp.key, pass > 0);
      } catch (e) { if (run === sp.run) shown(e, sp.canvas); return; }
      if (run !== sp.run) return;
      // A plain loop: Uint8Array.from(string, map) took 20–50 ms of the page's main thread
      // per pass, which delayed the 2D views' draws behind it.
      const text = atob(d.pixels), bytes = new Uint8Array(text.length);
      for (let i = 0; i < text.length; ++i) bytes[i] = text.charCodeAt(i);
      const px = new Float32Array(bytes.buffer);
      for (let i = 0; i < px.length; ++i) sp.acc[i] += px[i] * spp;
      sp.samples += spp;
      plot.image($(sp.canvas), sp.acc, sp.samples, SPHERE_SIZE, state.exposure);
      if (pass === 0) { drawn(sp.canvas); latency.sphere(token); }
      if (sp === spheres.a)
        $("sphere-readout").textContent = `${sp.samples} samples per pixel; drag on the image to move the light` +
          (comparing() ? "; B on the right" : "");
    }
  }
  function moveLight(ev) {
    if (!(ev.buttons & 1)) return;
    const c = $("sphere"), r = c.getBoundingClientRect();
    let x = (2 * (ev.clientX - r.left)) / r.width - 1, y = 1 - (2 * (ev.clientY - r.top)) / r.height;
    const len = Math.hypot(x, y);
    if (len > 0.999) { x *= 0.999 / len; y *= 0.999 / len; }
    state.light_x = +x.toFixed(3); state.light_y = +y.toFixed(3);
    saveHash();
    updateSphere();
  }

  async function updateLobe() {
    const token = latency.expect("lobe");
    try {
      const request = { theta_i: state.theta_i, count: 181 };
      const [d, db] = await Promise.all([api.post("/api/lobe", body(request), "lobe"),
        comparing() ? api.post("/api/lobe", body(request, true, state.material_b), "lobe_b") : null]);
      // A material that transmits has its lobe below the surface too (f_t, f_cos_t).
      plot.lobe($("lobe"), d, d[state.lobe], d.channels,
        db && { values: db[state.lobe], channels: db.channels, below: db[state.lobe + "_t"] }, d[state.lobe + "_t"]);
      drawn("lobe");
      const i = d.theta_o.findIndex((t) => t >= d.mirror);
      $("lobe-readout").textContent = `${state.lobe === "f" ? "f" : "f·cos θo"} at the mirror direction θo = ${d.mirror}°: ` +
        JSON.stringify(d[state.lobe][i]);
    } catch (e) { shown(e, "lobe"); } finally { latency.done(token, "lobe"); }
  }

  async function updateSlice() {
    const token = latency.expect("slice");
    try {
      const request = { phi_d: state.phi_d, size: 90 };
      if (comparing()) request.compare = state.material_b;
      // Three panels side by side when comparing: the figure spans the grid's width.
      const c = $("slice");
      c.width = comparing() ? 720 : 480;
      c.height = comparing() ? 230 : 320;
      c.style.maxWidth = c.width + "px";
      $("slice-view").style.gridColumn = comparing() ? "1 / -1" : "";
      sliceData = await api.post("/api/slice", body(request, false), "slice");
      if (sliceData.lo === null) {
        sliceData = null;
        plot.message($("slice"), "f is 0 at every pixel (a delta lobe has no finite f)");
        return;
      }
      slicePanel = plot.slice($("slice"), sliceData);
      drawn("slice");
      probeSlice();
      $("slice-readout").textContent = state.spectral ? "the slice is in RGB (luminance), as gonio slice" :
        "move the cursor over the slice to read f";
    } catch (e) { sliceData = null; shown(e, "slice"); } finally { latency.done(token, "slice"); }
  }

  // The cursor: the pixel's value at once, then f in RGB at its centre from the server.
  async function sliceCursor(ev) {
    if (!sliceData || !slicePanel) return;
    const c = $("slice"), r = c.getBoundingClientRect();
    const x = ((ev.clientX - r.left) * c.width) / r.width - slicePanel.x;
    const y = ((ev.clientY - r.top) * c.height) / r.height - slicePanel.y;
    const n = sliceData.size;
    const px = Math.floor((x / slicePanel.s) * n), py = Math.floor((y / slicePanel.s) * n);
    if (px < 0 || py < 0 || px >= n || py >= n) return;
    const u = (px + 0.5) / n;
    const thetaH = (sliceData.sqrt_theta_h ? u * u : u) * 90, thetaD = (1 - (py + 0.5) / n) * 90;
    const v = sliceData.values[py * n + px];
    const where = `θh ${thetaH.toFixed(2)}°, θd ${thetaD.toFixed(2)}°, φd ${sliceData.phi_d}°: `;
    let text = v < 0 ? "below the horizon" : "luminance of f " + plot.fmt(v) + " /sr";
    if (sliceData.values_compare && v >= 0) {
      const vb = sliceData.values_compare[py * n + px];
      text += `; B ${plot.fmt(vb)} /sr, (B − A) / A = ${v > 0 ? plot.fmt((vb - v) / v) : "n/a"}`;
    }
    $("slice-readout").textContent = where + text;
    if (sliceData.values_compare) return;
    if (v < 0) return;
    try {
      const p = await api.post("/api/slice_point", body({ theta_h: thetaH, theta_d: thetaD, phi_d: sliceData.phi_d }, false), "slice_point");
      const r = $("slice-readout");
      r.textContent = where + "luminance " + plot.fmt(p.luminance) + " /sr, f = " + JSON.stringify(p.f);
      // What the cursor read, for the browser test: the angles and f.
      Object.assign(r.dataset, { thetaH, thetaD, phiD: sliceData.phi_d, f: JSON.stringify(p.f) });
    } catch (e) { /* a newer position, or the material changed */ }
  }
  // state.probe = {px, py}: a pointer moved over that pixel of the slice once it is drawn
  // (the browser test's cursor, without a driver).
  function probeSlice() {
    if (!state.probe || !slicePanel || !sliceData) return;
    const c = $("slice"), r = c.getBoundingClientRect(), n = sliceData.size;
    const x = slicePanel.x + ((state.probe.px + 0.5) / n) * slicePanel.s, y = slicePanel.y + ((state.probe.py + 0.5) / n) * slicePanel.s;
    c.dispatchEvent(new MouseEvent("mousemove", { clientX: r.left + (x * r.width) / c.width, clientY: r.top + (y * r.height) / c.height }));
  }

  // Albedo: a first estimate with 256 samples per angle follows the slider (a layered
  // material's random walks take ~6 ms of server time at that count, 91 ms at 4,096), then
  // the same request with 4,096 samples, at the server's background priority, refines it —
  // aborted, like the first, by a newer input. Either is an unbiased estimate; the readout
  // names the count and the standard error.
  const ALBEDO_SAMPLES = [256, 4096];
  async function updateAlbedo() {
    const token = latency.expect("albedo");
    for (const samples of ALBEDO_SAMPLES) {
      if (!await drawAlbedo(samples)) break;
      latency.done(token, "albedo");
    }
    latency.done(token, "albedo");
  }
  async function drawAlbedo(samples) {
    try {
      const request = { count: 19, samples };
      const refining = samples > ALBEDO_SAMPLES[0];
      const [d, db] = await Promise.all([api.post("/api/albedo", body(request), "albedo", refining),
        comparing() ? api.post("/api/albedo", body(request, true, state.material_b), "albedo_b", refining) : null]);
      const series = [];
      let max = 1;
      // A: reflectance solid, transmittance dashed, albedo dotted; B: reflectance and
      // transmittance in long dashes, thin.
      for (const [data, isB] of [[d, false], [db, true]]) {
        if (!data) continue;
        const channels = plot.grey(data.reflectance) && plot.grey(data.transmittance) ? 1 : data.albedo[0].length;
        const colours = channels === 1 ? ["#222"] : plot.CHANNEL_COLOURS;
        for (const a of data.albedo) for (const v of a) max = Math.max(max, v);
        for (let c = 0; c < channels; ++c) {
          if (isB) {
            series.push({ x: data.theta, y: data.reflectance.map((v) => v[c]), color: colours[c], dash: [12, 4], width: 1, label: "B reflectance", legendColor: "#222" });
            series.push({ x: data.theta, y: data.transmittance.map((v) => v[c]), color: colours[c], dash: [12, 4, 2, 4], width: 1, label: "B transmittance", legendColor: "#222" });
            continue;
          }
          series.push({ x: data.theta, y: data.reflectance.map((v) => v[c]), color: colours[c], label: "reflectance", legendColor: "#222" });
          series.push({ x: data.theta, y: data.transmittance.map((v) => v[c]), color: colours[c], dash: [6, 4], label: "transmittance", legendColor: "#222" });
          series.push({ x: data.theta, y: data.albedo.map((v) => v[c]), color: colours[c], dash: [1, 3], width: 1, label: "albedo ρhd(ωo)", legendColor: "#222" });
          // Not reciprocal: the light's figure (light arriving along θ) beside the view's.
          if (data.reflectance_light) {
            const light = data.reflectance_light.map((v, i) => v[c] + data.transmittance_light[i][c]);
            for (const v of light) max = Math.max(max, v);
            series.push({ x: data.theta, y: light, color: colours[c], dash: [8, 3, 1, 3], width: 1, label: "light-side albedo (not reciprocal)", legendColor: "#222" });
          }
        }
      }
      plot.lines($("albedo"), { xRange: [0, 90], yRange: [0, Math.ceil(max * 10) / 10], xLabel: "θo (view)", yLabel: "fraction", series });
      drawn("albedo");
      $("albedo-readout").textContent = `normal incidence: reflectance ${JSON.stringify(d.reflectance[0].map((v) => +v.toPrecision(4)))}, ` +
        `transmittance ${JSON.stringify(d.transmittance[0].map((v) => +v.toPrecision(4)))}` + (d.exact[0] ? " (exact)" : ` (${d.samples} samples per angle, standard error ≤ ${plot.fmt(Math.max(...d.stderr.flat()))}` +
        (samples < ALBEDO_SAMPLES[ALBEDO_SAMPLES.length - 1] ? "; refining…)" : ")")) +
        (d.reflectance_light ? "; not reciprocal: the light-side albedo (light arriving along θ) is drawn apart" : "");
      return !d.exact.every((x) => x) || (db && !db.exact.every((x) => x));
    } catch (e) { shown(e, "albedo"); return false; }
  }

  async function updateFresnel() {
    const token = latency.expect("fresnel");
    try {
      const request = { count: 181 };
      let [d, db] = await Promise.all([api.post("/api/fresnel", body(request), "fresnel"),
        comparing() ? api.post("/api/fresnel", body(request, true, state.material_b), "fresnel_b") : null]);
      let note = "";
      if (d.interface === null) {
        note = "no interface in this material: η from the field below. ";
        d = await api.post("/api/fresnel", { eta: state.eta, count: 181, wavelength: state.spectral ? state.wavelength : undefined }, "fresnel");
      }
      const colours = d.channels.length === 1 ? ["#222"] : plot.CHANNEL_COLOURS;
      const series = [], markers = [];
      d.channels.forEach((ch, c) => {
        for (const [side, faded] of [["outside", false], ["inside", true]]) {
          const s = ch[side];
          if (!s) continue;
          const colour = faded ? "#999" : colours[c];
          const tag = faded ? " (inside)" : "";
          series.push({ x: d.theta, y: s.R, color: colour, label: "R" + tag, legendColor: faded ? "#999" : "#222" });
          series.push({ x: d.theta, y: s.Rs, color: colour, dash: [6, 4], label: "Rs" + tag, legendColor: faded ? "#999" : "#222" });
          series.push({ x: d.theta, y: s.Rp, color: colour, dash: [1, 3], label: "Rp" + tag, legendColor: faded ? "#999" : "#222" });
          if (c === 0) {
            markers.push({ x: s.brewster, label: (s.pseudo_brewster ? "pseudo-Brewster " : "Brewster ") + s.brewster.toFixed(2) + "°" + tag, color: faded ? "#999" : "#7a3db8", row: markers.length });
            if (s.critical !== null) markers.push({ x: s.critical, label: "critical " + s.critical.toFixed(2) + "°" + tag, color: "#e69500", row: markers.length });
          }
        }
      });
      // B's interface, from outside, in thin long dashes (R) and dash-dots (Rs, Rp).
      if (db && db.interface !== null) {
        const bColours = db.channels.length === 1 ? ["#222"] : plot.CHANNEL_COLOURS;
        db.channels.forEach((ch, c) => {
          const s = ch.outside;
          series.push({ x: db.theta, y: s.R, color: bColours[c], dash: [12, 4], width: 1, label: "B R", legendColor: "#222" });
          series.push({ x: db.theta, y: s.Rs, color: bColours[c], dash: [12, 4, 2, 4], width: 1, label: "B Rs", legendColor: "#222" });
          series.push({ x: db.theta, y: s.Rp, color: bColours[c], dash: [2, 6], width: 1, label: "B Rp", legendColor: "#222" });
        });
        note += `B: ${db.interface}, R(0°) = ${+db.channels[0].outside.R[0].toPrecision(6)}. `;
      } else if (db) {
        note += "B has no single interface. ";
      }
      plot.lines($("fresnel"), { xRange: [0, 90], yRange: [0, 1], xLabel: "θ (incidence)", yLabel: "reflectance", series, markers });
      drawn("fresnel");
      const ch = d.channels[0].outside;
      $("fresnel-readout").textContent = note + `${d.interface}: η = ${+ch.eta.toPrecision(6)}` + (ch.k ? `, k = ${+ch.k.toPrecision(6)}` : "") +
        `, R(0°) = ${+ch.R[0].toPrecision(6)}`;
    } catch (e) { shown(e, "fresnel"); } finally { latency.done(token, "fresnel"); }
  }

  async function runCheck() {
    const out = $("check-result");
    out.textContent = "running gonio check…";
    $("check").disabled = true;
    try {
      const d = await api.post("/api/check", { bsdf: state.material }, "check");
      const table = document.createElement("table");
      table.className = "check";
      table.innerHTML = "<tr><th>property</th><th>figure</th><th>threshold</th><th></th><th>where / how</th></tr>";
      for (const p of d.properties) {
        const tr = document.createElement("tr");
        const cells = [p.name, p.figure === null ? "n/a" : plot.fmt(p.figure), plot.fmt(p.threshold),
          p.pass ? (p.applicable === false ? "n/a" : "pass") : "FAIL", p.reason || p.detail || ""];
        cells.forEach((t, i) => {
          const td = document.createElement("td");
          td.textContent = t;
          if (i === 3) td.className = p.pass ? "pass" : "fail";
          tr.append(td);
        });
        table.append(tr);
      }
      out.textContent = d.pass ? "every property holds" : "some properties FAIL";
      out.append(table);
    } catch (e) {
      if (!api.isAbort(e)) out.textContent = e.message;
    } finally {
      $("check").disabled = false;
    }
  }

  // gonio fit from the page: the table becomes A, the fitted model B, compared.
  async function runFit() {
    const out = $("fit-result");
    out.textContent = "fitting (gonio fit)…";
    $("fit").disabled = true;
    try {
      const d = await api.post("/api/fit", { file: $("fit-file").value, model: $("fit-model").value }, "fit");
      state.material = d.measured;
      state.material_b = d.material;
      state.compare = true;
      buildEditor();
      onMaterialEdited();
      out.textContent = `error ${plot.fmt(d.error)} (${d.metric}) in ${d.seconds.toFixed(2)} s: ` + JSON.stringify(d.material);
    } catch (e) {
      if (!api.isAbort(e)) out.textContent = e.message;
    } finally {
      $("fit").disabled = false;
    }
  }

  async function onJsonEdited() {
    const text = $("json").value;
    try {
      await api.post("/api/validate", { bsdf: text }, "validate");
    } catch (e) {
      if (!api.isAbort(e)) status(e.message, "error");
      return;
    }
    state.material = JSON.parse(text);
    buildEditor();
    schedule();
  }

  function wire() {
    $("theta-i").addEventListener("input", (e) => { state.theta_i = +e.target.value; $("theta-i-out").textContent = state.theta_i + "°"; saveHash(); updateLobe(); updateLobe3d(); });
    $("lobe3d").addEventListener("mousedown", (e) => { turning = { x: e.clientX, y: e.clientY }; });
    $("lobe3d").addEventListener("mousemove", turnLobe3d);
    $("phi-d").addEventListener("input", (e) => { state.phi_d = +e.target.value; $("phi-d-out").textContent = state.phi_d + "°"; saveHash(); updateSlice(); });
    for (const r of document.querySelectorAll("input[name=lobe-mode]"))
      r.addEventListener("change", () => { state.lobe = r.value; saveHash(); updateLobe(); drawLobe3d(); });
    $("spectral").addEventListener("change", (e) => { state.spectral = e.target.checked; syncControls(); schedule(); });
    $("wavelength").addEventListener("input", (e) => { state.wavelength = +e.target.value; $("wavelength-out").textContent = state.wavelength + " nm"; schedule(); });
    $("fresnel-eta").addEventListener("input", (e) => { const v = parseFloat(e.target.value); if (v > 0) { state.eta = v; saveHash(); updateFresnel(); } });
    $("json").addEventListener("input", () => { clearTimeout(timer); timer = setTimeout(onJsonEdited, 150); });
    $("slice").addEventListener("mousemove", sliceCursor);
    $("sphere").addEventListener("mousedown", moveLight);
    $("sphere").addEventListener("mousemove", moveLight);
    $("exposure").addEventListener("input", (e) => {
      state.exposure = +e.target.value; saveHash();
      for (const sp of Object.values(spheres))
        if (sp.samples && !$(sp.canvas).hidden) plot.image($(sp.canvas), sp.acc, sp.samples, SPHERE_SIZE, state.exposure);
    });
    $("environment").addEventListener("input", (e) => { state.environment = +e.target.value; saveHash(); updateSphere(); });
    $("environment-map").addEventListener("change", (e) => { state.environment_map = e.target.value; saveHash(); updateSphere(); });
    $("check").addEventListener("click", runCheck);
    $("fit").addEventListener("click", runFit);
    $("compare").addEventListener("change", (e) => {
      state.compare = e.target.checked;
      if (state.compare && !state.material_b) state.material_b = JSON.parse(JSON.stringify(state.material));
      buildEditor();
      schedule();
    });
    $("permalink").addEventListener("click", async () => {
      saveHash();
      try { await navigator.clipboard.writeText(location.href); status("link copied: " + location.href, "ok"); }
      catch (e) { status("link: " + location.href, "ok"); }
    });
    $("export-json").addEventListener("click", () => {
      const a = document.createElement("a");
      a.href = URL.createObjectURL(new Blob([JSON.stringify(state.material, null, 2) + "\n"], { type: "application/json" }));
      a.download = (state.material.type || "material") + ".json";
      a.click();
    });
    for (const b of document.querySelectorAll("button.png")) b.addEventListener("click", () => plot.exportPNG($(b.dataset.canvas), b.dataset.canvas));
    window.addEventListener("hashchange", () => { if (loadHash()) { syncControls(); buildEditor(); onMaterialEdited(); } });
  }

  async function start() {
    try {
      const registry = await api.get("/api/materials");
      editor.setRegistry(registry);
      $("version").textContent = "gonio " + registry.version;
      $("wavelength").min = registry.wavelength.min;
      $("wavelength").max = registry.wavelength.max;
      const data = await api.get("/api/data");
      editor.setDataFiles(data.files);
      const tables = data.files.filter((f) => f.endsWith(".binary"));
      if (tables.length && registry.fit_models.length) {
        for (const [id, names] of [["fit-file", tables], ["fit-model", registry.fit_models]])
          for (const n of names) {
            const o = document.createElement("option");
            o.value = o.textContent = n;
            $(id).append(o);
          }
        $("fit-panel").hidden = false;
      }
    } catch (e) {
      status("cannot reach the server: " + e.message, "error");
      return;
    }
    if (!loadHash()) state.material = editor.example("roughconductor");
    syncControls();
    wire();
    buildEditor();
    onMaterialEdited();
  }

  start();
})();
