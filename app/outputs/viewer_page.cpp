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
  #view, #video { max-width: 100%; background: #000; min-width: 320px; min-height: 240px; }
  #transport { font-weight: 400; color: #9ab; margin-left: 12px; }
  table { border-collapse: collapse; min-width: 260px; }
  td { padding: 2px 8px; border-bottom: 1px solid #333; vertical-align: top; }
  td:first-child { color: #9ab; white-space: nowrap; }
  td.num { font-variant-numeric: tabular-nums; text-align: right; }
  .bad { color: #f86; }
  #error { color: #f86; padding: 0 12px; }
</style>
</head>
<body>
<header>probeless<span id="transport"></span></header>
<main>
  <video id="video" muted autoplay playsinline hidden></video>
  <img id="view" alt="live view" hidden>
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
// The picture: WebRTC through WHEP (H.264, a tenth of MJPEG's bandwidth) when the appliance
// offers it, else the MJPEG stream. No STUN/TURN: the appliance's ICE host candidates are on
// addresses it was configured to use ([webrtc] ice_addresses). The offer is sent once ICE
// gathering is done (no trickle, which the server does not take). Frames decoded are counted
// on <body> (data-frames, and data-frames2s: the two seconds after the first), for anyone
// wondering whether WebRTC plays, and posted to an embedding page (the Chromium test's).
const video = document.getElementById("video");
const transport = document.getElementById("transport");
let mjpeg = false;
let whepResource = null;
function report() {
  if (window.parent !== window) window.parent.postMessage(Object.assign({}, document.body.dataset), "*");
}
function showMjpeg(reason) {
  transport.textContent = "MJPEG" + (reason ? " (WebRTC: " + reason + ")" : "");
  document.body.dataset.transport = "mjpeg";
  video.hidden = true;
  view.hidden = false;
  if (!mjpeg) view.src = "/stream";
  mjpeg = true;
  report();
}
// The service restarting ends the stream: reconnect instead of showing a broken image.
view.addEventListener("error", () => {
  if (mjpeg) setTimeout(() => { view.src = "/stream?t=" + Date.now(); }, 1000);
});
function countFrames() {
  let frames = 0, first = 0;
  const tick = (now) => {
    frames += 1;
    if (!first) first = now;
    document.body.dataset.frames = frames;
    if (now - first <= 2000) document.body.dataset.frames2s = frames;
    report();
    video.requestVideoFrameCallback(tick);
  };
  if ("requestVideoFrameCallback" in video) video.requestVideoFrameCallback(tick);
}
function gathered(pc, ms) {
  return new Promise((resolve) => {
    if (pc.iceGatheringState === "complete") return resolve();
    const done = () => { if (pc.iceGatheringState === "complete") resolve(); };
    pc.addEventListener("icegatheringstatechange", done);
    setTimeout(resolve, ms);
  });
}
async function playWebRtc() {
  const pc = new RTCPeerConnection();
  pc.addTransceiver("video", {direction: "recvonly"});
  const firstFrame = new Promise((resolve) => {
    pc.ontrack = (e) => {
      video.srcObject = e.streams[0] || new MediaStream([e.track]);
      video.addEventListener("loadeddata", resolve, {once: true});
    };
  });
  await pc.setLocalDescription(await pc.createOffer());
  await gathered(pc, 1000);
  const r = await fetch("/whep", {method: "POST", headers: {"Content-Type": "application/sdp"},
                                  body: pc.localDescription.sdp});
  const text = await r.text();
  if (r.status !== 201) { pc.close(); throw new Error("HTTP " + r.status + " " + text.trim()); }
  whepResource = new URL(r.headers.get("Location"), location.href).href;
  await pc.setRemoteDescription({type: "answer", sdp: text});
  const timeout = new Promise((_, reject) => setTimeout(() => reject(new Error("no frame in 5 s")), 5000));
  try {
    await Promise.race([firstFrame, timeout]);
  } catch (e) {
    pc.close();
    stopWhep();
    throw e;
  }
  pc.addEventListener("connectionstatechange", () => {
    if (pc.connectionState === "failed" || pc.connectionState === "closed") {
      pc.close();
      stopWhep();
      start();  // the service restarted, or the network moved: negotiate again
    }
  });
  transport.textContent = "WebRTC";
  document.body.dataset.transport = "webrtc";
  report();
  view.hidden = true;
  video.hidden = false;
  video.play().catch(() => {});
}
function stopWhep() {
  if (whepResource) fetch(whepResource, {method: "DELETE", keepalive: true}).catch(() => {});
  whepResource = null;
}
async function start() {
  if (!("RTCPeerConnection" in window)) return showMjpeg("not in this browser");
  try {
    await playWebRtc();
  } catch (e) {
    showMjpeg(e.message);
  }
}
window.addEventListener("pagehide", stopWhep);
countFrames();
start();
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
