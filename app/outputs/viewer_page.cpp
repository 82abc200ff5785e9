#include "app/outputs/viewer_page.hpp"

namespace probeless {
namespace {

// The table knows a few keys of the service's status (docs/outputs.md "GET /status"):
// "fps", "stages" ({name: {p50_ms, p99_ms}}), "sources" ({name: state or {state}}) and
// this server's "http"; anything else is listed as flattened key/value rows, so a new
// field shows up without a change here.
constexpr std::string_view kPage = R"html(<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<meta name="viewport" content="width=device-width, initial-scale=1">
<title>probeless</title>
<style>
  body { margin: 0; background: #111; color: #ddd; font: 14px/1.4 system-ui, sans-serif; }
  header { padding: 6px 12px; background: #222; font-weight: 600; }
  main { display: flex; flex-wrap: wrap; gap: 12px; padding: 12px; align-items: flex-start; }
  #view { max-width: 100%; background: #000; min-width: 320px; min-height: 240px; }
  table { border-collapse: collapse; min-width: 260px; }
  td { padding: 2px 8px; border-bottom: 1px solid #333; vertical-align: top; }
  td:first-child { color: #9ab; white-space: nowrap; }
  td.num { font-variant-numeric: tabular-nums; text-align: right; }
  .bad { color: #f86; }
  #error { color: #f86; padding: 0 12px; }
</style>
</head>
<body>
<header>probeless</header>
<main>
  <img id="view" src="/stream" alt="live view">
  <table id="status"><tbody><tr><td>status</td><td>waiting</td></tr></tbody></table>
</main>
<div id="error"></div>
<script>
"use strict";
const table = document.querySelector("#status tbody");
const error = document.getElementById("error");
const view = document.getElementById("view");

function fmt(v) {
  if (typeof v === "number") return Number.isInteger(v) ? String(v) : v.toFixed(2);
  if (v === null || v === undefined) return "-";
  return String(v);
}
function row(key, value, cls) {
  const tr = document.createElement("tr");
  const k = document.createElement("td");
  const v = document.createElement("td");
  k.textContent = key;
  v.textContent = fmt(value);
  if (typeof value === "number") v.className = "num";
  if (cls) v.classList.add(cls);
  tr.append(k, v);
  table.append(tr);
}
function flatten(prefix, value) {
  if (value !== null && typeof value === "object" && !Array.isArray(value)) {
    for (const [k, v] of Object.entries(value)) flatten(prefix ? prefix + "." + k : k, v);
  } else if (Array.isArray(value)) {
    row(prefix, value.length + " items");
  } else {
    row(prefix, value);
  }
}
function render(s) {
  table.replaceChildren();
  const rest = Object.assign({}, s);
  if ("fps" in rest) { row("fps", rest.fps); delete rest.fps; }
  if (rest.stages && typeof rest.stages === "object") {
    for (const [name, t] of Object.entries(rest.stages)) {
      if (t && typeof t === "object" && "p50_ms" in t) {
        row("stage " + name, fmt(t.p50_ms) + " / " + fmt(t.p99_ms) + " ms (p50 / p99)");
      } else {
        row("stage " + name, t);
      }
    }
    delete rest.stages;
  }
  if (rest.sources && typeof rest.sources === "object") {
    for (const [name, src] of Object.entries(rest.sources)) {
      const state = src && typeof src === "object" ? src.state : src;
      row("source " + name, state, state === "streaming" ? "" : "bad");
    }
    delete rest.sources;
  }
  const http = rest.http;
  delete rest.http;
  flatten("", rest);
  if (http) {
    row("viewers", http.clients);
    for (const c of http.stream_clients || []) {
      row("  " + c.peer, c.frames_sent + " sent, " + c.drops + " dropped");
    }
  }
}
async function poll() {
  try {
    const r = await fetch("/status", {cache: "no-store"});
    if (!r.ok) throw new Error("HTTP " + r.status);
    render(await r.json());
    error.textContent = "";
  } catch (e) {
    error.textContent = "status: " + e.message;
  }
}
// The service restarting ends the stream: reconnect instead of showing a broken image.
view.addEventListener("error", () => {
  setTimeout(() => { view.src = "/stream?t=" + Date.now(); }, 1000);
});
poll();
setInterval(poll, 1000);
</script>
</body>
</html>
)html";

}  // namespace

std::string_view viewer_html() {
  return kPage;
}

}  // namespace probeless
