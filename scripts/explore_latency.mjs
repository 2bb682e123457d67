// The explorer's latency in a real browser (issue 36: after a slider moves, every 2D view
// is redrawn within 100 ms; the server's time per request at most 30 ms). Starts
// `gonio explore` and headless Chromium, drives the page through the DevTools protocol with
// real mouse input (a slider dragged step by step, a pause between steps), and reads what the
// page measured itself (window.gonioLatency: from each input event to the end of the
// redraw of every view it changes) and the server's time of each request (its
// Server-Timing header, through the browser's Resource Timing). Needs Node ≥ 20 (its
// WebSocket, behind --experimental-websocket before Node 22) and nothing from npm.
//
//   node --experimental-websocket scripts/explore_latency.mjs [--gonio build/bin/gonio]
//     [--chromium /usr/bin/chromium] [--steps 12] [--pause 250] [--types] [--json FILE]
//
// --types adds a drag of the first slider of every registry type's example. Prints one
// table line per drag; exit status 0 unless something failed to run (the figures are
// reported, not judged: tests/explore judges the page's recorder, docs/benchmarks.md the
// figures).

import { spawn } from "node:child_process";
import { mkdtempSync, rmSync, writeFileSync } from "node:fs";
import { tmpdir } from "node:os";
import { join } from "node:path";
import { createInterface } from "node:readline";

const args = process.argv.slice(2);
const opt = (name, dflt) => {
  const i = args.indexOf("--" + name);
  return i < 0 ? dflt : args[i + 1];
};
const flag = (name) => args.includes("--" + name);
const gonio = opt("gonio", "build/bin/gonio");
const chromium = opt("chromium", "/usr/bin/chromium");
const steps = +opt("steps", 12);
const pause = +opt("pause", 250);
const sleep = (ms) => new Promise((r) => setTimeout(r, ms));

// The first line a child prints (on stdout or stderr) that matches `re`.
function firstMatch(stream, re, what) {
  return new Promise((resolve, reject) => {
    const rl = createInterface({ input: stream });
    const timer = setTimeout(() => reject(new Error("no " + what + " within 20 s")), 20000);
    rl.on("line", (line) => {
      const m = line.match(re);
      if (m) { clearTimeout(timer); resolve(m); }
    });
  });
}

// A minimal DevTools protocol client over one WebSocket.
async function connect(wsUrl) {
  const ws = new WebSocket(wsUrl);
  await new Promise((resolve, reject) => { ws.onopen = resolve; ws.onerror = reject; });
  let id = 0;
  const waiting = new Map();
  ws.onmessage = (m) => {
    const msg = JSON.parse(m.data);
    if (msg.id && waiting.has(msg.id)) {
      const { resolve, reject } = waiting.get(msg.id);
      waiting.delete(msg.id);
      if (msg.error) reject(new Error(JSON.stringify(msg.error)));
      else resolve(msg.result);
    }
  };
  const send = (method, params = {}) => new Promise((resolve, reject) => {
    waiting.set(++id, { resolve, reject });
    ws.send(JSON.stringify({ id, method, params }));
  });
  return { send, close: () => ws.close() };
}

const children = [];
const profile = mkdtempSync(join(tmpdir(), "gonio-latency-"));
function cleanup() {
  for (const c of children) if (c.exitCode === null) c.kill("SIGTERM");
  try { rmSync(profile, { recursive: true, force: true, maxRetries: 5 }); } catch { /* Chromium still closing */ }
}
process.on("exit", cleanup);

async function main() {
  const server = spawn(gonio, ["explore", "--port", "0"], { stdio: ["ignore", "pipe", "inherit"] });
  children.push(server);
  const [url] = await firstMatch(server.stdout, /^http:\/\/\S+\/$/, "URL from gonio explore");
  const browser = spawn(chromium, ["--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars",
    "--remote-debugging-port=0",
    // A headless page counts as a background one: its renderer process would be niced and
    // its timers throttled, as no page a person looks at is.
    "--disable-renderer-backgrounding", "--disable-background-timer-throttling", "--disable-backgrounding-occluded-windows", "--user-data-dir=" + profile, "--window-size=1400,1200", "about:blank"],
  { stdio: ["ignore", "ignore", "pipe"] });
  children.push(browser);
  const [, port] = await firstMatch(browser.stderr, /DevTools listening on ws:\/\/[^:]+:(\d+)\//, "DevTools port");
  const targets = await (await fetch(`http://127.0.0.1:${port}/json/list`)).json();
  const page = await connect(targets.find((t) => t.type === "page").webSocketDebuggerUrl);
  await page.send("Page.enable");
  await page.send("Runtime.enable");
  const evaluate = async (expression) => {
    const r = await page.send("Runtime.evaluate", { expression, returnByValue: true, awaitPromise: true });
    if (r.exceptionDetails) throw new Error(expression + ": " + JSON.stringify(r.exceptionDetails));
    return r.result.value;
  };
  const waitFor = async (expression, what, ms = 20000) => {
    for (const end = Date.now() + ms; Date.now() < end; await sleep(50)) if (await evaluate(expression)) return;
    throw new Error("timed out waiting for " + what);
  };
  const mouse = (type, x, y) => page.send("Input.dispatchMouseEvent", { type, x, y, button: "left", buttons: type === "mouseReleased" ? 0 : 1, clickCount: 1 });

  const views = ["lobe", "lobe3d", "slice", "albedo", "fresnel", "sphere"];
  async function open(material) {
    const hash = encodeURIComponent(JSON.stringify({ material }));
    await page.send("Page.navigate", { url: url + "#" + hash });
    await waitFor(`(() => { const c = ${JSON.stringify(views)}.map((v) => document.getElementById(v));
      return c.every((x) => x && (x.dataset.drawn || x.dataset.message)); })()`, "the first drawing", 30000);
    // Every request's timing from now on (the default buffer holds 250).
    await evaluate("performance.setResourceTimingBufferSize(100000); performance.clearResourceTimings(); true");
  }

  // Drags the slider `selector` (the first match) by `steps` moves of 4 % of its width.
  async function drag(label, selector) {
    const box = await evaluate(`(() => { const s = ${selector}; if (!s) return null; s.scrollIntoView({ block: "center" });
      const r = s.getBoundingClientRect(); return { x: r.left, y: r.top + r.height / 2, w: r.width }; })()`);
    if (!box) return null;
    const before = await evaluate("window.gonioLatency.summary().records.length");
    let x = box.x + box.w * 0.3;
    await mouse("mousePressed", x, box.y);
    await sleep(pause);
    for (let i = 0; i < steps; ++i) {
      x += box.w * 0.04 * (i < steps / 2 ? 1 : -1);
      await mouse("mouseMoved", x, box.y);
      await sleep(pause);
    }
    await mouse("mouseReleased", x, box.y);
    await sleep(Math.max(pause, 300));
    const s = await evaluate("window.gonioLatency.summary()");
    const server = await evaluate(`(() => { const by = {};
      for (const e of performance.getEntriesByType("resource")) {
        const t = e.serverTiming.find((x) => x.name === "app");
        if (!t) continue;
        const path = new URL(e.name).pathname.replace("/api/", "");
        (by[path] = by[path] || []).push(t.duration);
      }
      return by; })()`);
    await evaluate("performance.clearResourceTimings(); true");
    return { label, records: s.records.slice(before), superseded: s.superseded, server };
  }

  const median = (a) => { const b = [...a].sort((x, y) => x - y); return b.length ? b[Math.floor((b.length - 1) / 2)] : NaN; };
  const max = (a) => (a.length ? Math.max(...a) : NaN);
  const f = (v) => (Number.isFinite(v) ? v.toFixed(1) : "—");
  const results = [];
  function report(r) {
    if (!r) return;
    results.push(r);
    const totals = r.records.map((x) => x.total);
    const perView = {};
    for (const rec of r.records) for (const [v, t] of Object.entries(rec.views)) (perView[v] = perView[v] || []).push(t);
    const sphere = r.records.map((x) => x.sphere).filter((x) => x !== undefined);
    const server = Object.entries(r.server).map(([p, t]) => `${p} ${f(median(t))}/${f(max(t))}`).join(", ");
    console.log(`${r.label}: ${r.records.length} inputs, redraw median ${f(median(totals))} ms, max ${f(max(totals))} ms; ` +
      `per view (median) ${Object.entries(perView).map(([v, t]) => `${v} ${f(median(t))}`).join(", ")}; ` +
      `sphere's first image median ${f(median(sphere))} ms; server ms (median/max) ${server}`);
  }

  const param = (name) => `[...document.querySelectorAll("#editor .param")].filter((r) => r.querySelector(".name")?.textContent === ${JSON.stringify(name)})
    .map((r) => r.querySelector("input[type=range]")).find((x) => x)`;
  const cases = [
    ["diffuse reflectance", { type: "diffuse", reflectance: 0.5 }, "reflectance"],
    ["roughconductor alpha", { type: "roughconductor", alpha: 0.2, material: "Cu" }, "alpha"],
    ["roughdielectric alpha", { type: "roughdielectric", alpha: 0.2, eta: 1.5 }, "alpha"],
    ["blend weight", { type: "blend", weight: 0.3, bsdfs: [{ type: "diffuse", reflectance: 0.7 }, { type: "roughconductor", alpha: 0.15, material: "Au" }] }, "weight"],
    ["layered top alpha", { type: "layered", top: { type: "roughdielectric", alpha: 0.1, eta: 1.5 }, bottom: { type: "diffuse", reflectance: [0.7, 0.2, 0.1] } }, "alpha"],
  ];
  for (const [label, material, name] of cases) {
    await open(material);
    report(await drag(label, param(name)));
  }
  // The angle sliders, with the rough conductor.
  await open(cases[1][1]);
  report(await drag("θi (roughconductor)", `document.getElementById("theta-i")`));
  report(await drag("φd (roughconductor)", `document.getElementById("phi-d")`));
  if (flag("types")) {
    const registry = await (await fetch(url + "api/materials", { headers: { Host: new URL(url).host } })).json();
    for (const t of registry.types) {
      await open(t.example);
      const r = await drag("example " + t.name, `document.querySelector("#editor input[type=range]")`);
      if (r) report(r); else console.log(`example ${t.name}: no slider`);
    }
  }
  const errors = await evaluate(`document.getElementById("errors").textContent`);
  if (errors) console.log("page errors: " + errors.trim());
  if (opt("json")) writeFileSync(opt("json"), JSON.stringify(results, null, 1));
  page.close();
}

main().then(() => { cleanup(); process.exit(0); }, (e) => { console.error("explore_latency: " + e.message); cleanup(); process.exit(1); });
