// vessel-view front end: linked 3D and flattened views of one field over time.
import * as THREE from 'three';
import { loadData } from './data.js';
import { buildLayout, showError } from './ui.js';
import { COLORMAP_NAMES, DIVERGING, colormapBytes, colormapTexture, drawColorbar, formatValue } from './colormaps.js';
import { fieldUniforms } from './material.js';
import { MapLocator } from './locate.js';
import { View3d } from './view3d.js';
import { View2d } from './view2d.js';

const QMAX = 65535;

// Time step pair and blend weight for time t: steps i, i + 1 and mix in [0, 1).
function stepsAt(times, t, interpolate) {
  const last = times.length - 1;
  if (last === 0 || t <= times[0]) return [0, Math.min(1, last), 0];
  if (t >= times[last]) return [last, last, 0];
  let i = 0;
  while (i + 1 < last && times[i + 1] <= t) i++;
  const f = (t - times[i]) / (times[i + 1] - times[i]);
  if (!interpolate) return f < 0.5 ? [i, i, 0] : [i + 1, i + 1, 0];
  return [i, i + 1, f];
}

function fixed(x, radius) {
  const decimals = Math.max(0, 4 - Math.floor(Math.log10(Math.max(radius, 1e-30))));
  return x.toFixed(Math.min(decimals, 8));
}

async function start() {
  const timings = {};
  let clock = performance.now();
  const lap = (name) => { const now = performance.now(); timings[name] = now - clock; clock = now; };
  const data = await loadData();
  lap('decode_ms');
  const { meta } = data;
  const $ = buildLayout(meta.title);
  const nv = data.positions.length / 3;

  const texture = colormapTexture(COLORMAP_NAMES[0]);
  const uniforms = fieldUniforms(texture);
  const shared = { index: new THREE.BufferAttribute(data.indices, 1), uniforms };
  const locator = new MapLocator(data.uv, data.indices);
  lap('grid_ms');
  shared.mapUv = new Float32Array(2 * nv);
  for (let i = 0; i < nv; i++) {
    shared.mapUv[2 * i] = (data.uv[2 * i] - locator.min[0]) / locator.size[0];
    shared.mapUv[2 * i + 1] = (data.uv[2 * i + 1] - locator.min[1]) / locator.size[1];
  }

  let dirty = true;
  const requestRender = () => { dirty = true; };
  // The camera's 'change' event already fires inside the constructor, before view3d is set.
  let view3d = null;
  view3d = new View3d($('canvas3d'), data, shared, () => { if (view3d) updateRecut(); requestRender(); });
  const view2d = new View2d($('canvas2d'), data, shared, requestRender);

  // One normalized uint16 attribute per time step and field, uploaded on first use.
  const fields = data.fields.map((field) => ({
    ...field,
    steps: field.times.map((_, i) => new THREE.BufferAttribute(field.values.subarray(i * nv, (i + 1) * nv), 1, true)),
  }));

  const state = { field: 0, time: 0, playing: false, speed: 1, interpolate: true, hover: null, hoverSource: null };

  function currentField() { return fields[state.field]; }

  // Per frame while playing: the blend weight always, the two step attributes only when the
  // pair changes (a new pair makes three.js re-bind the vertex attributes of both views).
  let bound = null;
  function applyTime() {
    const field = currentField();
    const [a, b, f] = stepsAt(field.times, state.time, state.interpolate);
    if (!bound || bound.field !== field || bound.a !== a || bound.b !== b) {
      for (const view of [view3d, view2d]) {
        view.geometry.setAttribute('valueA', field.steps[a]);
        view.geometry.setAttribute('valueB', field.steps[b]);
      }
      bound = { field, a, b };
    }
    uniforms.mixT.value = f;
    state.steps = [a, b, f];
    $('time').value = state.time;
    $('time-label').textContent = field.times.length > 1
      ? `t = ${state.time.toFixed(3)} s (step ${a + 1}${f > 0 ? '-' + (b + 1) : ''} of ${field.times.length})`
      : 'static field';
    updateReadout();
    requestRender();
  }

  function setRange(min, max) {
    uniforms.rangeMin.value = min;
    uniforms.rangeMax.value = max;
    $('min').value = formatValue(min);
    $('max').value = formatValue(max);
    drawColorbar($('colorbar'), $('colormap').value, min, max, currentField().unit);
    requestRender();
  }

  function autoRange() {
    const field = currentField();
    if ($('colormap').value === DIVERGING) {
      const m = Math.max(Math.abs(field.lo), Math.abs(field.hi));
      setRange(-m, m);
    } else {
      setRange(field.lo, field.hi);
    }
  }

  function selectField(index) {
    state.field = index;
    const field = currentField();
    uniforms.dataLo.value = field.lo;
    uniforms.dataHi.value = field.hi;
    const times = field.times;
    $('time').min = times[0];
    $('time').max = times[times.length - 1];
    $('time').disabled = times.length < 2;
    $('play').disabled = times.length < 2;
    state.time = Math.min(Math.max(state.time, times[0]), times[times.length - 1]);
    if (field.colormap && COLORMAP_NAMES.includes(field.colormap)) $('colormap').value = field.colormap;
    setColormap($('colormap').value);
    autoRange();
    applyTime();
  }

  function setColormap(name) {
    // The cut stays visible: lime on the blue-white-red map, red on viridis (which has no red).
    view3d.seam.material.color.set(name === DIVERGING ? 0x39ff14 : 0xff2020);
    $('seam-colour').textContent = name === DIVERGING ? 'green' : 'red';
    const next = colormapTexture(name);
    uniforms.cmap.value.dispose();
    uniforms.cmap.value = next;
    drawColorbar($('colorbar'), name, uniforms.rangeMin.value, uniforms.rangeMax.value, currentField().unit);
    requestRender();
  }

  // Field value at vertex k for the current time (as the GPU computes it).
  function vertexValue(k) {
    const field = currentField();
    const [a, b, f] = state.steps;
    const qa = field.values[a * nv + k] / QMAX, qb = field.values[b * nv + k] / QMAX;
    return field.lo + (qa + (qb - qa) * f) * (field.hi - field.lo);
  }

  // Field `index` at barycentric point `bary` of face f and time t, from the stored steps
  // (linear in time, as the GPU blends them).
  function valueInFace(index, f, bary, t) {
    const field = fields[index];
    const [a, b, w] = stepsAt(field.times, t, true);
    let value = 0;
    for (let k = 0; k < 3; k++) {
      const vtx = data.indices[3 * f + k];
      const qa = field.values[a * nv + vtx] / QMAX, qb = field.values[b * nv + vtx] / QMAX;
      value += bary[k] * (field.lo + (qa + (qb - qa) * w) * (field.hi - field.lo));
    }
    return value;
  }

  function updateReadout() {
    const hit = state.hover;
    if (!hit) {
      $('readout').textContent = 'hover a view to read a value';
      return;
    }
    const field = currentField();
    let value = 0;
    for (let c = 0; c < 3; c++) value += hit.bary[c] * vertexValue(data.indices[3 * hit.face + c]);
    const p = hit.point.map((x, i) => x + meta.centre[i]);
    $('readout').textContent = `${field.name} = ${formatValue(value)}${field.unit ? ' ' + field.unit : ''}` +
      ` at (${p.map((x) => fixed(x, view3d.radius)).join(', ')})`;
    state.hoverValue = value;
  }

  // Links a map location (face + barycentric) to markers on both views.
  function setHover(hit, source) {
    if (hit) {
      const point = [0, 0, 0], mapPoint = [0, 0];
      for (let c = 0; c < 3; c++) {
        const k = data.indices[3 * hit.face + c];
        for (let d = 0; d < 3; d++) point[d] += hit.bary[c] * data.positions[3 * k + d];
        for (let d = 0; d < 2; d++) mapPoint[d] += hit.bary[c] * data.uv[2 * k + d];
      }
      hit.point = point;
      hit.mapPoint = mapPoint;
    }
    state.hover = hit;
    state.hoverSource = hit ? source : null;
    view3d.showMarker(hit ? hit.point : null);
    view2d.showMarker(hit ? hit.mapPoint : null);
    updateReadout();
    requestRender();
  }

  // Hover is resolved once per animation frame for the latest pointer position: the 3D pick is a
  // render plus a pixel read-back, too costly for every pointer event.
  let pendingHover = null;
  function resolveHover() {
    const { view, x, y } = pendingHover;
    pendingHover = null;
    if (view === '2d') {
      const [u, v] = view2d.toMap(x, y);
      setHover(locator.locate(u, v), '2d');
      return;
    }
    const q = view3d.pick(x, y);
    if (!q) {
      setHover(null, '3d');
      return;
    }
    const u = locator.min[0] + q[0] * locator.size[0], v = locator.min[1] + q[1] * locator.size[1];
    setHover(locator.locate(u, v, 1), '3d');
  }
  $('canvas2d').addEventListener('pointermove', (event) => {
    pendingHover = { view: '2d', x: event.offsetX, y: event.offsetY };
  });
  $('canvas3d').addEventListener('pointermove', (event) => {
    if (event.buttons) return; // orbiting
    pendingHover = { view: '3d', x: event.offsetX, y: event.offsetY };
  });
  for (const id of ['canvas2d', 'canvas3d']) {
    $(id).addEventListener('pointerleave', () => { pendingHover = null; setHover(null, id); });
  }

  function updateRecut() {
    const p = view3d.camera.position;
    const xyz = [p.x, p.y, p.z].map((x, i) => fixed(x + meta.centre[i], view3d.radius)).join(' ');
    $('recut').textContent = `${meta.flatten_command} --viewpoint ${xyz}`;
    $('recut').title = `or a new page: ${meta.view_command} --viewpoint ${xyz}`;
  }
  $('copy').addEventListener('click', async () => {
    const text = $('recut').textContent;
    try {
      await navigator.clipboard.writeText(text);
    } catch (err) {
      const range = document.createRange();
      range.selectNodeContents($('recut'));
      getSelection().removeAllRanges();
      getSelection().addRange(range);
      document.execCommand('copy');
    }
    $('copy').textContent = 'copied';
    setTimeout(() => { $('copy').textContent = 'copy'; }, 1200);
  });

  fields.forEach((field, i) => $('field').add(new Option(field.unit ? `${field.name} [${field.unit}]` : field.name, i)));
  COLORMAP_NAMES.forEach((name) => $('colormap').add(new Option(name, name)));
  $('field').addEventListener('change', () => selectField(Number($('field').value)));
  $('colormap').addEventListener('change', () => { setColormap($('colormap').value); autoRange(); });
  $('min').addEventListener('change', () => setRange(Number($('min').value), uniforms.rangeMax.value));
  $('max').addEventListener('change', () => setRange(uniforms.rangeMin.value, Number($('max').value)));
  $('auto').addEventListener('click', autoRange);
  $('time').addEventListener('input', () => { state.time = Number($('time').value); applyTime(); });
  $('speed').addEventListener('change', () => { state.speed = Number($('speed').value); });
  $('interpolate').addEventListener('change', () => { state.interpolate = $('interpolate').checked; applyTime(); });
  $('play').addEventListener('click', () => {
    state.playing = !state.playing;
    $('play').textContent = state.playing ? 'pause' : 'play';
    lastFrame = null;
  });

  const resize = () => {
    for (const view of [view3d, view2d]) {
      const box = view.canvas.parentElement.getBoundingClientRect();
      view.resize(box.width, box.height);
    }
    requestRender();
  };
  new ResizeObserver(resize).observe($('canvas3d').parentElement);
  resize();

  let lastFrame = null;
  let framesDrawn = 0;
  function frame(now) {
    if (pendingHover) resolveHover();
    if (state.playing) {
      const times = currentField().times;
      const t0 = times[0], t1 = times[times.length - 1];
      if (lastFrame !== null) {
        state.time += ((now - lastFrame) / 1000) * state.speed;
        if (state.time > t1) state.time = t0 + ((state.time - t0) % Math.max(t1 - t0, 1e-9));
        applyTime();
      }
      lastFrame = now;
    }
    if (dirty) {
      dirty = false;
      view3d.render();
      view2d.render();
      framesDrawn++;
    }
    requestAnimationFrame(frame);
  }

  const initial = meta.fields.findIndex((f) => f.times.length > 1);
  $('field').value = String(Math.max(initial, 0));
  selectField(Math.max(initial, 0));
  updateRecut();
  lap('setup_ms');
  view3d.render();
  view2d.render();
  lap('first_frame_ms');
  requestAnimationFrame(frame);

  // Hooks for the end-to-end test and for scripting the page from the console.
  window.vesselViewer = {
    state,
    view2d,
    view3d,
    locator,
    timings,
    setTime(t) { state.time = t; applyTime(); },
    renderNow() { view3d.render(); view2d.render(); },
    // RGB of the map view at canvas (CSS pixel) position (x, y), drawn just before: the drawing
    // buffer is not preserved once the page has shown it.
    mapPixel(x, y) {
      this.renderNow();
      const gl = view2d.renderer.getContext(), r = view2d.canvas.width / view2d.canvas.clientWidth;
      const px = new Uint8Array(4);
      gl.readPixels(Math.floor(x * r), view2d.canvas.height - 1 - Math.floor(y * r), 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, px);
      return Array.from(px.slice(0, 3));
    },
    // Canvas (CSS pixel) position in the 2D view of the centroid of face f.
    faceOnMap(f) {
      let u = 0, v = 0;
      for (let c = 0; c < 3; c++) {
        const k = data.indices[3 * f + c];
        u += data.uv[2 * k] / 3;
        v += data.uv[2 * k + 1] / 3;
      }
      return view2d.toCanvas(u, v);
    },
    // Canvas (CSS pixel) position in the 3D view of a point (centre-relative, as stored).
    pointOn3d(p) {
      const q = new THREE.Vector3(p[0], p[1], p[2]).project(view3d.camera);
      return [(q.x + 1) / 2 * view3d.canvas.clientWidth, (1 - q.y) / 2 * view3d.canvas.clientHeight];
    },
    vertexOn3d(k) {
      const i = k % nv;
      return this.pointOn3d([data.positions[3 * i], data.positions[3 * i + 1], data.positions[3 * i + 2]]);
    },
    // The colour the views give `value` with the current colormap and range (8-bit RGB).
    colourOf(value) {
      const lut = colormapBytes($('colormap').value);
      const { rangeMin, rangeMax } = uniforms;
      const s = Math.min(Math.max((value - rangeMin.value) / (rangeMax.value - rangeMin.value), 0), 1);
      const x = s * 255, i = Math.min(Math.floor(x), 254), f = x - i;
      return [0, 1, 2].map((c) => lut[4 * i + c] * (1 - f) + lut[4 * i + 4 + c] * f);
    },
    fieldRange(index) { return [fields[index].lo, fields[index].hi]; },
    fieldTimes(index) { return fields[index].times; },
    // Field `index` at face f's centroid and time t, from the stored steps (linear in time).
    valueAtCentroid(index, f, t) { return valueInFace(index, f, [1 / 3, 1 / 3, 1 / 3], t); },
    // Field `index` at time t where the map view draws canvas pixel (x, y) (CSS pixels, as
    // mapPixel reads it): interpolated at that device pixel's centre in the triangle under it, as
    // the GPU shades it. null when the pixel centre is off the map.
    valueAtPixel(index, x, y, t) {
      const r = view2d.canvas.width / view2d.canvas.clientWidth;
      const [u, v] = view2d.toMap((Math.floor(x * r) + 0.5) / r, (Math.floor(y * r) + 0.5) / r);
      const hit = locator.locate(u, v);
      return hit ? valueInFace(index, hit.face, hit.bary, t) : null;
    },
    // Centroid of face f in 3D (centre-relative).
    faceCentroid3d(f) {
      const c = [0, 0, 0];
      for (let k = 0; k < 3; k++)
        for (let d = 0; d < 3; d++) c[d] += data.positions[3 * data.indices[3 * f + k] + d] / 3;
      return c;
    },
    nFaces: data.indices.length / 3,
    nVertices: nv,
    get framesDrawn() { return framesDrawn; },
  };
  document.body.dataset.ready = '1';
}

start().catch((err) => {
  console.error(err);
  showError('vessel-view: ' + (err && err.message ? err.message : err));
  document.body.dataset.error = String(err && err.message ? err.message : err);
});
