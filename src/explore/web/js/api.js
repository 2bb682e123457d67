// The server's JSON API (docs/explore.md). One request in flight per view: a newer
// request of the same view aborts the older one, so a slider never queues stale work.
"use strict";

const api = (() => {
  const inflight = new Map();
  // This page's id: the server stops a view's older request when a newer one comes.
  const session = Math.random().toString(36).slice(2, 14);

  // `background`: a refinement, computed by the server at a lower priority.
  async function request(method, path, body, key, background = false) {
    if (key && inflight.has(key)) inflight.get(key).abort();
    const controller = new AbortController();
    if (key) inflight.set(key, controller);
    try {
      const init = { method, signal: controller.signal, headers: key ? { "X-Gonio-Session": session, "X-Gonio-View": key } : {} };
      if (background) init.headers["X-Gonio-Priority"] = "background";
      if (body !== undefined) {
        init.headers["Content-Type"] = "application/json";
        init.body = JSON.stringify(body);
      }
      const response = await fetch(path, init);
      const data = await response.json();
      if (!response.ok) {
        const error = new Error(data.error || ("HTTP " + response.status));
        error.superseded = response.status === 409;
        throw error;
      }
      return data;
    } finally {
      if (key && inflight.get(key) === controller) inflight.delete(key);
    }
  }

  // An aborted fetch, or an answer the server stopped because a newer request came (409).
  const isAbort = (e) => e && (e.name === "AbortError" || e.superseded);

  return {
    get: (path, key) => request("GET", path, undefined, key),
    post: (path, body, key, background) => request("POST", path, body, key, background),
    isAbort,
  };
})();
