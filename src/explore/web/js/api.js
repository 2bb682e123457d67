// The server's JSON API (docs/explore.md). One request in flight per view: a newer
// request of the same view aborts the older one, so a slider never queues stale work.
"use strict";

const api = (() => {
  const inflight = new Map();

  async function request(method, path, body, key) {
    if (key && inflight.has(key)) inflight.get(key).abort();
    const controller = new AbortController();
    if (key) inflight.set(key, controller);
    try {
      const init = { method, signal: controller.signal, headers: {} };
      if (body !== undefined) {
        init.headers["Content-Type"] = "application/json";
        init.body = JSON.stringify(body);
      }
      const response = await fetch(path, init);
      const data = await response.json();
      if (!response.ok) throw new Error(data.error || ("HTTP " + response.status));
      return data;
    } finally {
      if (key && inflight.get(key) === controller) inflight.delete(key);
    }
  }

  const isAbort = (e) => e && e.name === "AbortError";

  return {
    get: (path, key) => request("GET", path, undefined, key),
    post: (path, body, key) => request("POST", path, body, key),
    isAbort,
  };
})();
