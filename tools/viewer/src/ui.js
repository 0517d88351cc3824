// The page layout and its styles; returns the elements main.js wires up.

const CSS = `
  html, body { margin: 0; height: 100%; background: #111317; color: #ddd;
    font: 13px system-ui, sans-serif; }
  #vv-app { display: flex; flex-direction: column; height: 100%; }
  .vv-bar { display: flex; flex-wrap: wrap; align-items: center; gap: 6px 14px; padding: 6px 10px;
    background: #1f232b; }
  .vv-bar label { display: flex; align-items: center; gap: 5px; }
  .vv-bar input[type=number] { width: 82px; }
  #vv-title { font-weight: 600; margin-right: 8px; }
  #vv-views { flex: 1; display: flex; min-height: 0; gap: 2px; }
  .vv-view { position: relative; flex: 1; min-width: 0; }
  .vv-view canvas { width: 100%; height: 100%; display: block; touch-action: none; }
  .vv-view .vv-caption { position: absolute; left: 8px; top: 6px; color: #aaa; pointer-events: none; }
  #vv-time { flex: 1; min-width: 200px; }
  #vv-readout { min-width: 330px; font-family: ui-monospace, monospace; }
  #vv-recut { font-family: ui-monospace, monospace; user-select: all; background: #111317;
    padding: 3px 6px; border-radius: 3px; max-width: 70vw; overflow-x: auto; white-space: nowrap; }
  #vv-error { position: absolute; inset: 30% 20% auto 20%; background: #5a1d1d; padding: 16px;
    border-radius: 6px; display: none; }
  button, select, input { font: inherit; }
`;

export function buildLayout(title) {
  const style = document.createElement('style');
  style.textContent = CSS;
  document.head.appendChild(style);
  const app = document.createElement('div');
  app.id = 'vv-app';
  app.innerHTML = `
    <div class="vv-bar">
      <span id="vv-title"></span>
      <label>field <select id="vv-field"></select></label>
      <label>colormap <select id="vv-colormap"></select></label>
      <label>min <input id="vv-min" type="number" step="any"></label>
      <label>max <input id="vv-max" type="number" step="any"></label>
      <button id="vv-auto" title="Range of the field over all time steps">auto range</button>
      <canvas id="vv-colorbar" width="300" height="34"></canvas>
    </div>
    <div id="vv-views">
      <div class="vv-view"><canvas id="vv-canvas3d"></canvas>
        <span class="vv-caption">3D: drag = orbit, wheel = zoom, right drag = pan; <span id="vv-seam-colour">red</span> = cut</span></div>
      <div class="vv-view"><canvas id="vv-canvas2d"></canvas>
        <span class="vv-caption">flattened map: wheel = zoom, drag = pan, double click = reset</span></div>
    </div>
    <div class="vv-bar">
      <button id="vv-play">play</button>
      <input id="vv-time" type="range" step="any">
      <span id="vv-time-label"></span>
      <label>speed <select id="vv-speed"></select></label>
      <label><input id="vv-interpolate" type="checkbox" checked> interpolate</label>
      <span id="vv-readout">hover a view to read a value</span>
    </div>
    <div class="vv-bar">
      <span>re-cut facing this camera:</span><span id="vv-recut"></span>
      <button id="vv-copy">copy</button>
    </div>
    <div id="vv-error"></div>`;
  document.body.appendChild(app);
  document.title = title;
  const $ = (id) => document.getElementById('vv-' + id);
  $('title').textContent = title;
  for (const s of [0.1, 0.25, 0.5, 1, 2]) {
    const option = new Option(s + 'x', s, s === 1, s === 1);
    $('speed').add(option);
  }
  return $;
}

export function showError(message) {
  const box = document.getElementById('vv-error');
  if (!box) {
    document.body.textContent = message;
    return;
  }
  box.textContent = message;
  box.style.display = 'block';
}
