// End-to-end test of the viewer in headless Chromium (Debian's /usr/bin/chromium driven by
// playwright-core; no browser download). Generates a page from a real mesh with vessel-view,
// then checks that both views draw coloured pixels, that moving the time slider changes the map,
// and that hovering one view marks the same wall point on the other. Saves a screenshot.
//
//   node test/e2e.mjs --exe build/bin/vessel-view --mesh MESH.ply --workdir DIR
//                     [--pulse-exe build/bin/vessel-pulse --fields-mesh MESH.vtp]
//                     [--screenshot docs/images/viewer.png] [--chromium /usr/bin/chromium]
// With --pulse-exe, a second page shows a series read with --fields (vessel-pulse's synthetic
// pulse over FIELDS-MESH's points, as a .pvd): its map must show the stored steps blended in
// time, and the screenshot is taken of that page.
import { execFileSync } from 'node:child_process';
import { mkdirSync } from 'node:fs';
import { resolve, dirname } from 'node:path';
import { pathToFileURL } from 'node:url';
import { launchChromium } from './browser.mjs';

function parseArgs(argv) {
  const args = { chromium: process.env.VESSEL_CHROMIUM || '/usr/bin/chromium' };
  for (let i = 0; i < argv.length; i += 2) args[argv[i].replace(/^--/, '')] = argv[i + 1];
  for (const key of ['exe', 'mesh', 'workdir'])
    if (!args[key]) throw new Error(`missing --${key}; see the usage at the top of e2e.mjs`);
  return args;
}

const args = parseArgs(process.argv.slice(2));
let failures = 0;
const started = Date.now();
function check(ok, what, detail) {
  const s = ((Date.now() - started) / 1000).toFixed(1);
  console.log(`${ok ? 'ok  ' : 'FAIL'} ${what}${detail ? ': ' + detail : ''} [${s} s]`);
  if (!ok) failures++;
}

mkdirSync(args.workdir, { recursive: true });
const html = resolve(args.workdir, 'viewer-e2e.html');
execFileSync(args.exe, [args.mesh, '-o', html, '--demo-field', '-q'], { stdio: 'inherit' });

// The page of a --fields series: starts, lists the series, draws it, the slider changes the map,
// and a map pixel has the colour of the stored steps blended at the current time.
async function fieldsPage(page, snapshot, frame) {
  const prefix = resolve(args.workdir, 'pulse');
  execFileSync(args['pulse-exe'], [args['fields-mesh'], prefix, '--name', 'WSS_synthetic', '-q'], { stdio: 'inherit' });
  const html2 = resolve(args.workdir, 'viewer-e2e-fields.html');
  execFileSync(args.exe, [args['fields-mesh'], '-o', html2, '--fields', prefix + '.pvd', '-q'], { stdio: 'inherit' });
  await page.goto(pathToFileURL(html2).href);
  await page.waitForFunction(() => document.body.dataset.ready || document.body.dataset.error, null, { timeout: 60000 });
  const bootError = await page.evaluate(() => document.body.dataset.error || '');
  check(!bootError, 'the --fields page starts', bootError);
  if (bootError) return;
  const options = await page.locator('#vv-field option').allTextContents();
  const steps = await page.evaluate(() => window.vesselViewer.fieldTimes(Number(document.getElementById('vv-field').value)).length);
  check(options.some((o) => o.startsWith('WSS_synthetic')) && steps === 90, 'the --fields series is offered and shown',
    `fields ${options.join(', ')}; ${steps} steps shown`);
  const first = await snapshot();
  for (const id of ['vv-canvas3d', 'vv-canvas2d'])
    check(first[id].coloured > 0.02 * first[id].total, `--fields page: ${id} draws coloured pixels`, `${first[id].coloured} coloured`);
  const slider = await page.locator('#vv-time').boundingBox();
  await page.mouse.click(slider.x + slider.width * 0.17, slider.y + slider.height / 2);
  const moved = await snapshot();
  check(moved['vv-canvas2d'].changed > 0.01 * moved['vv-canvas2d'].total, '--fields page: the slider changes the map',
    `${moved['vv-canvas2d'].changed} pixels changed`);
  // Hover a mid-index face: the map pixel there vs the series' value at that pixel's centre,
  // interpolated from the stored steps at the current time (not a step's own value).
  const box2d = await page.locator('#vv-canvas2d').boundingBox();
  const [mx, my] = await page.evaluate(() => window.vesselViewer.faceOnMap(Math.floor(window.vesselViewer.nFaces / 2)));
  await page.mouse.move(box2d.x + mx, box2d.y + my);
  await frame();
  const c = await page.evaluate(([x, y]) => {
    const v = window.vesselViewer, f = Math.floor(v.nFaces / 2), t = v.state.time, k = v.state.field;
    const px = v.mapPixel(x, y);
    const [lo, hi] = v.fieldRange(k);
    return { px, want: v.colourOf(v.valueAtPixel(k, x, y, t)), t, steps: v.state.steps, shown: v.state.hoverValue,
      value: v.valueAtCentroid(k, f, t), span: hi - lo };
  }, [mx, my]);
  const err = Math.max(...c.px.map((x, i) => Math.abs(x - c.want[i])));
  check(c.steps[2] > 0 && c.steps[2] < 1 && err <= 2, '--fields page: the map shows the series blended in time',
    `t = ${c.t.toFixed(3)} s between steps ${c.steps[0] + 1} and ${c.steps[1] + 1}; pixel rgb(${c.px}) vs rgb(${c.want.map(Math.round)})`);
  check(Math.abs(c.shown - c.value) < 0.01 * c.span, '--fields page: the read-out is the series value there',
    `${c.shown.toFixed(4)} vs ${c.value.toFixed(4)} (range ${c.span.toFixed(3)})`);
  await page.evaluate(() => window.vesselViewer.setTime(0.31));
}

const browser = await launchChromium(args.chromium, args.workdir);
try {
  const { page } = browser;
  const errors = [];
  page.on('pageerror', (err) => errors.push(String(err)));
  page.on('console', (msg) => { if (msg.type() === 'error') errors.push(msg.text()); });
  // Offline: any request that is not the page itself or a data: URL fails the test.
  const requests = [];
  page.on('request', (req) => {
    const url = req.url();
    if (!url.startsWith('file:') && !url.startsWith('data:')) requests.push(url);
  });
  await page.goto(pathToFileURL(html).href);
  await page.waitForFunction(() => document.body.dataset.ready || document.body.dataset.error, null, { timeout: 60000 });
  const bootError = await page.evaluate(() => document.body.dataset.error || '');
  check(!bootError, 'page starts', bootError);
  if (bootError) throw new Error('the page did not start: ' + bootError);

  // Renders both views, then counts pixels of each canvas: non-background, coloured (saturated)
  // and hover-marker magenta. Also returns the raw pixels of the 2D view for comparisons.
  const frame = () => page.evaluate(() => new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(r))));
  const snapshot = async () => {
    await frame();
    return page.evaluate(() => {
      window.vesselViewer.renderNow();
      const out = {};
      for (const id of ['vv-canvas3d', 'vv-canvas2d']) {
        const canvas = document.getElementById(id);
        const copy = document.createElement('canvas');
        copy.width = canvas.width;
        copy.height = canvas.height;
        const ctx = copy.getContext('2d');
        ctx.drawImage(canvas, 0, 0);
        const px = ctx.getImageData(0, 0, copy.width, copy.height).data;
        let foreground = 0, coloured = 0, magenta = 0;
        for (let i = 0; i < px.length; i += 4) {
          const r = px[i], g = px[i + 1], b = px[i + 2];
          if (Math.abs(r - 27) + Math.abs(g - 30) + Math.abs(b - 36) > 12) foreground++;
          if (Math.max(r, g, b) - Math.min(r, g, b) > 40) coloured++;
          if (r > 200 && g < 80 && b > 200) magenta++;
        }
        out[id] = { total: px.length / 4, foreground, coloured, magenta };
        if (id === 'vv-canvas2d') {
          // Pixels that changed since the previous snapshot (by more than 30 in R+G+B).
          const last = window.e2eLast2d;
          let changed = 0;
          for (let i = 0; last && i < px.length; i += 4)
            if (Math.abs(px[i] - last[i]) + Math.abs(px[i + 1] - last[i + 1]) + Math.abs(px[i + 2] - last[i + 2]) > 30) changed++;
          out[id].changed = changed;
          window.e2eLast2d = px;
        }
      }
      return out;
    });
  };

  const first = await snapshot();
  for (const id of ['vv-canvas3d', 'vv-canvas2d']) {
    const s = first[id];
    check(s.coloured > 0.02 * s.total, `${id} draws coloured pixels`,
      `${s.coloured} coloured, ${s.foreground} non-background of ${s.total}`);
  }

  // Time slider, moved with the mouse: a click at 40% of its track.
  const before = await page.evaluate(() => window.vesselViewer.state.time);
  const slider = await page.locator('#vv-time').boundingBox();
  await page.mouse.click(slider.x + slider.width * 0.4, slider.y + slider.height / 2);
  const after = await page.evaluate(() => window.vesselViewer.state.time);
  const moved = await snapshot();
  const diff = moved['vv-canvas2d'].changed;
  check(after > before, 'the time slider moves the time', `${before.toFixed(3)} s -> ${after.toFixed(3)} s`);
  check(diff > 0.01 * first['vv-canvas2d'].total, 'moving the time slider changes the 2D map',
    `${diff} of ${first['vv-canvas2d'].total} pixels changed`);

  // Hover the map at the centroid of a mid-index triangle: the 3D view shows the marker.
  check(moved['vv-canvas3d'].magenta === 0, 'no marker before hovering', `${moved['vv-canvas3d'].magenta} magenta pixels`);
  const box2d = await page.locator('#vv-canvas2d').boundingBox();
  const [mx, my] = await page.evaluate(() => window.vesselViewer.faceOnMap(Math.floor(window.vesselViewer.nFaces / 2)));
  await page.mouse.move(box2d.x + mx, box2d.y + my);
  const hovered = await snapshot();
  const readout = await page.locator('#vv-readout').textContent();
  const hover = await page.evaluate(() => {
    const v = window.vesselViewer, f = Math.floor(v.nFaces / 2);
    const m = v.view3d.marker.position, c = v.faceCentroid3d(f);
    return { face: v.state.hover?.face, expected: f, marker: v.view3d.marker.visible,
      offset: Math.hypot(m.x - c[0], m.y - c[1], m.z - c[2]) / v.view3d.radius };
  });
  check(hover.marker && hovered['vv-canvas3d'].magenta > 0, 'hovering the map marks the wall point in 3D',
    `${hovered['vv-canvas3d'].magenta} marker pixels in 3D`);
  // The map point hovered is face f's centroid: the 3D marker must sit at f's 3D centroid.
  check(hover.face === hover.expected && hover.offset < 1e-3, 'the 3D marker is the hovered wall point',
    `face ${hover.face} (expected ${hover.expected}), marker off the 3D centroid by ${hover.offset.toExponential(2)} x mesh radius`);
  check(/=\s*-?[\d.]/.test(readout), 'hovering shows the value', readout);
  // The GPU blend of the two steps around t: the map's pixel at the hovered point (the ring
  // marker leaves its centre free) has the colour of the pulse blended at t at that pixel's own
  // centre. The read-out at the centroid is the demo pulse computed from the geodesic field:
  // sin(2 pi (t / 1.8 - 1.5 d / d_max)).
  const colour = await page.evaluate(([x, y]) => {
    const v = window.vesselViewer, f = Math.floor(v.nFaces / 2), t = v.state.time;
    const px = v.mapPixel(x, y);
    const d = v.valueAtCentroid(0, f, 0), dMax = v.fieldRange(0)[1];
    const expected = Math.sin(2 * Math.PI * (t / 1.8 - 1.5 * d / dMax));
    const atPixel = v.valueAtPixel(1, x, y, t);
    // The colours of the two stored steps around t, which a nearest-step display would show.
    const times = v.fieldTimes(1), [a, b] = v.state.steps;
    const stepColours = [times[a], times[b]].map((ts) => v.colourOf(v.valueAtPixel(1, x, y, ts)));
    return { pixel: px, want: v.colourOf(atPixel), atPixel, expected, shown: v.state.hoverValue, t,
      between: v.state.steps, stepColours };
  }, [mx, my]);
  const distance = (p, q) => Math.max(...p.map((c, i) => Math.abs(c - q[i])));
  const colourError = distance(colour.pixel, colour.want);
  const stepErrors = colour.stepColours.map((c) => distance(colour.pixel, c));
  check(colour.between[2] > 0 && colour.between[2] < 1 && colourError <= 2 && Math.min(...stepErrors) > colourError,
    'the map shows the value interpolated between two steps',
    `t = ${colour.t.toFixed(3)} s between steps ${colour.between[0] + 1} and ${colour.between[1] + 1}; value at the pixel ${colour.atPixel.toFixed(4)} ` +
    `-> rgb(${colour.want.map(Math.round)}), pixel rgb(${colour.pixel}); the steps' own colours are ` +
    `${stepErrors.map((e) => e.toFixed(1)).join(' and ')} levels away`);
  check(Math.abs(colour.shown - colour.expected) < 0.01, 'the read-out value is the pulse at that point',
    `${colour.shown.toFixed(4)} vs ${colour.expected.toFixed(4)}`);

  // Hover the 3D view where a vertex projects (the surface is under it); the map then shows
  // the marker.
  const box3d = await page.locator('#vv-canvas3d').boundingBox();
  let hit3d = null;
  for (let k = 0; k < 10 && !hit3d; k++) {
    const [x, y] = await page.evaluate((i) => window.vesselViewer.vertexOn3d(i), k * 997);
    await page.mouse.move(box3d.x + x, box3d.y + y);
    await frame();
    if (await page.evaluate(() => window.vesselViewer.state.hoverSource === '3d')) hit3d = [x, y];
  }
  const hovered3d = await snapshot();
  check(hit3d !== null && hovered3d['vv-canvas2d'].magenta > 0, 'hovering the 3D view marks the map point',
    hit3d ? `${hovered3d['vv-canvas2d'].magenta} marker pixels on the map` : 'no surface under the scanned points');
  if (hit3d) {
    // The wall point found through the GPU pick and the map must project back under the mouse.
    const [px, py] = await page.evaluate(() => window.vesselViewer.pointOn3d(window.vesselViewer.state.hover.point));
    const miss = Math.hypot(px - hit3d[0], py - hit3d[1]);
    check(miss < 3, 'the 3D pick finds the wall point under the mouse', `${miss.toFixed(2)} px from the mouse`);
  }

  // Play advances the time; pause stops it.
  await page.click('#vv-play');
  const t0 = await page.evaluate(() => window.vesselViewer.state.time);
  await page.waitForTimeout(700);
  await page.click('#vv-play');
  const t1 = await page.evaluate(() => window.vesselViewer.state.time);
  await page.waitForTimeout(300);
  const t2 = await page.evaluate(() => window.vesselViewer.state.time);
  check(t1 !== t0 && t2 === t1, 'play advances the time and pause stops it',
    `${t0.toFixed(3)} s -> ${t1.toFixed(3)} s, then ${t2.toFixed(3)} s after pausing`);

  // The field selector: the static geodesic distance, with viridis, redraws the map.
  await snapshot();
  await page.selectOption('#vv-field', '0');
  const geodesic = await snapshot();
  const cmap = await page.locator('#vv-colormap').inputValue();
  check(cmap === 'viridis' && geodesic['vv-canvas2d'].changed > 0.01 * geodesic['vv-canvas2d'].total,
    'the field selector switches field and colormap', `${cmap}, ${geodesic['vv-canvas2d'].changed} map pixels changed`);
  await page.selectOption('#vv-field', '1');
  await page.evaluate(() => window.vesselViewer.setTime(0.708));
  if (args['pulse-exe']) await fieldsPage(page, snapshot, frame);

  // Screenshot: mid-cycle, a hovered point, both views.
  if (args.screenshot) {
    const box2d = await page.locator('#vv-canvas2d').boundingBox();
    const [mx, my] = await page.evaluate(() => window.vesselViewer.faceOnMap(Math.floor(window.vesselViewer.nFaces / 2)));
    await page.mouse.move(box2d.x + mx, box2d.y + my);
    await frame();
    mkdirSync(dirname(resolve(args.screenshot)), { recursive: true });
    await page.screenshot({ path: args.screenshot });
    console.log(`screenshot: ${args.screenshot}`);
  }
  check(errors.length === 0, 'no page errors', errors.join(' | '));
  check(requests.length === 0, 'no network requests', requests.join(' '));
} finally {
  await browser.close();
}
if (failures) {
  console.log(`${failures} check(s) failed`);
  process.exit(1);
}
console.log('all viewer checks passed');
