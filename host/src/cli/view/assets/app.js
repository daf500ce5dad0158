// A placeholder until the page is written: shows the snapshot's summary.
"use strict";

async function show() {
  const state = await (await fetch("/api/state")).json();
  const errors = state.diagnostics.filter((d) => d.severity === "error").length;
  document.getElementById("state").textContent =
    `${state.file}: version ${state.version}${state.busy ? " (busy)" : ""}, ` +
    `${state.output.source_lines.length} output lines, ${state.diagnostics.length} diagnostics (${errors} errors), ` +
    `${state.path.pieces} toolpath pieces`;
}

show();
new EventSource("/api/events").addEventListener("snapshot", show);
