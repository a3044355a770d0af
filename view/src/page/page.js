// The live page: one EventSource on /stream; each message is one drawn frame (its SVG and
// its numbers, see view/src/hub.rs); controls are POSTed to /control. Nothing is drawn here:
// the SVG comes from the same Rust drawing code as `neurotac view --snapshot`.
"use strict";

const $ = (id) => document.getElementById(id);
let lastSeq = 0;
let skipped = 0;
let latencyMax = 0;
let state = "connecting";

// The server obeys only its own content type (a page of another site cannot send it).
function control(body) {
  return fetch("/control", {
    method: "POST",
    body,
    headers: { "Content-Type": "application/x-neurotac-control" },
  });
}

$("pause").addEventListener("click", () =>
  control(state === "paused" || state === "ended" ? "play" : "pause"));
$("step").addEventListener("click", () => control("step"));
$("seek").addEventListener("change", (e) => control("seek " + e.target.value));
$("speed").addEventListener("change", (e) => control("speed " + e.target.value));

function show(m, firstOfConnection) {
  if (lastSeq && !firstOfConnection && m.seq > lastSeq + 1) skipped += m.seq - lastSeq - 1;
  lastSeq = m.seq;
  state = m.state;
  $("view").innerHTML = m.svg;
  $("source").textContent = m.source;
  $("state").textContent = m.state;
  $("pause").textContent = { paused: "play", ended: "replay" }[m.state] || "pause";
  $("stream-time").textContent = m.t_s.toFixed(3);
  $("events-in").textContent = m.counts.events_in;
  $("after-filters").textContent = m.counts.after_filters;
  $("in-fields").textContent = m.counts.in_fields;
  $("taxel-spikes").textContent = m.counts.taxel_spikes;
  $("raster-spikes").textContent = m.raster_spikes;
  $("frame-seq").textContent = m.seq;
  $("frames-skipped").textContent = skipped;
  const d = m.decimation;
  const parts = [];
  if (d.drawn_share < 1)
    parts.push(`the event image shows ${(100 * d.drawn_share).toFixed(0)} % of the ` +
      `${d.events_since_last_frame} events since the last frame (each pixel's latest); all are counted`);
  if (d.speed_vs_realtime > 1.5)
    parts.push(`stream at ${d.speed_vs_realtime.toFixed(1)}× real time`);
  if (skipped) parts.push(`${skipped} frames skipped by this tab (it drew slower than they came)`);
  $("decimation").textContent = parts.join("; ");
  $("notice").hidden = !m.notice;
  $("notice").textContent = m.notice || "";
  const speed = $("speed");
  const value = m.speed === "realtime" ? "realtime" : m.speed.replace("×", "");
  if (![...speed.options].some((o) => o.value === value)) speed.add(new Option(m.speed, value));
  speed.value = value;
  // A camera is only watched live.
  for (const id of ["pause", "speed", "step", "seek"]) $(id).disabled = m.speed === "live";
}

// Event-to-screen latency, once `m` has been painted. The first frame of a connection was
// drawn before this tab came: not a latency.
function painted(m, firstOfConnection) {
  if (m.due_unix_ms === null || firstOfConnection) return;
  const latency = performance.timeOrigin + performance.now() - m.due_unix_ms;
  latencyMax = Math.max(latencyMax, latency);
  $("latency-ms").textContent = latency.toFixed(1);
  $("latency-max-ms").textContent = latencyMax.toFixed(1);
}

// A message is drawn as soon as it comes unless the previous drawing has not been painted
// yet; then only the newest waiting one is drawn once it has: a tab that draws slower than
// frames come skips the older ones (and counts them) instead of falling behind.
let newest = null;
let painting = false;

function drawNewest() {
  const { data, first } = newest;
  newest = null;
  painting = true;
  const m = JSON.parse(data);
  show(m, first);
  // Once the next animation frame has run, the drawing has been painted.
  requestAnimationFrame(() => setTimeout(() => {
    painted(m, first);
    painting = false;
    if (newest !== null) drawNewest();
  }, 0));
}

function connect() {
  const events = new EventSource("/stream");
  let first = true;
  events.onmessage = (e) => {
    newest = { data: e.data, first: first || (newest !== null && newest.first) };
    first = false;
    if (!painting) drawNewest();
  };
  events.onerror = () => {
    $("notice").hidden = false;
    $("notice").textContent = "lost the connection to neurotac view; retrying…";
  };
  events.onopen = () => {
    first = true;
    if ($("notice").textContent.startsWith("lost")) $("notice").hidden = true;
  };
}

connect();
