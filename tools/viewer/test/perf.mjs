// Measures a generated page in headless Chromium (docs/viewer.md, "Size and speed"). Not a test:
// with the default SwiftShader backend WebGL runs on the CPU, far slower than any real GPU.
//   node test/perf.mjs PAGE.html [--chromium /usr/bin/chromium] [--frames 30]
//        [--backend swiftshader|gl|vulkan] [--play-seconds 5] [--screenshot PNG]
// Prints one JSON line:
//   load_ms          navigation to the page's ready flag (parse + base64 decode + set-up + first frame)
//   timings          the page's own split of that: decode_ms, grid_ms, setup_ms, first_frame_ms
//   rss_mb           resident memory of all Chromium processes of this run (browser, renderer,
//                    GPU process), after load and after every step was shown; js_heap_mb likewise
//   frame_*          setTime + render of both views, until the GPU is done (readPixels)
//   submit_median_ms the JavaScript part of that (setting attributes and uniforms, three.js calls)
//   slider_*         a slider 'input' event: handler time (JS), and until both views show it
//   play_fps         frames the page's own animation loop drew per second while playing
//   renderer         the WebGL renderer string (SwiftShader = CPU)
import { readFileSync, readdirSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { resolve } from 'node:path';
import { pathToFileURL } from 'node:url';
import { launchChromium } from './browser.mjs';

const [page_path, ...rest] = process.argv.slice(2);
const opts = { chromium: '/usr/bin/chromium', frames: '30', backend: 'swiftshader', 'play-seconds': '5' };
for (let i = 0; i < rest.length; i += 2) opts[rest[i].replace(/^--/, '')] = rest[i + 1];

// Resident memory (MB) of every process whose command line names this run's profile directory.
function rssMb(profile) {
  let kb = 0;
  for (const pid of readdirSync('/proc').filter((p) => /^\d+$/.test(p))) {
    try {
      if (!readFileSync(`/proc/${pid}/cmdline`, 'utf8').includes(profile)) continue;
      const m = /VmRSS:\s+(\d+)/.exec(readFileSync(`/proc/${pid}/status`, 'utf8'));
      if (m) kb += Number(m[1]);
    } catch (err) { /* the process ended */ }
  }
  return Math.round(kb / 1024);
}

const browser = await launchChromium(opts.chromium, tmpdir(), opts.backend);
try {
  const { page, context, profile } = browser;
  const cdp = await context.newCDPSession(page);
  await cdp.send('Performance.enable');
  const heapMb = async () => {
    const { metrics } = await cdp.send('Performance.getMetrics');
    return Math.round(metrics.find((m) => m.name === 'JSHeapUsedSize').value / 1048576);
  };
  const t0 = Date.now();
  await page.goto(pathToFileURL(resolve(page_path)).href);
  await page.waitForFunction(() => document.body.dataset.ready || document.body.dataset.error, null, { timeout: 600000 });
  const loaded = Date.now() - t0;
  const error = await page.evaluate(() => document.body.dataset.error || '');
  if (error) throw new Error('the page did not start: ' + error);
  const memory = { rss_mb_loaded: rssMb(profile), js_heap_mb_loaded: await heapMb() };
  const result = await page.evaluate(async (frames) => {
    const v = window.vesselViewer;
    const gl = v.view2d.renderer.getContext(), gl3 = v.view3d.renderer.getContext();
    const px = new Uint8Array(4);
    const finish = () => { gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, px); gl3.readPixels(0, 0, 1, 1, gl3.RGBA, gl3.UNSIGNED_BYTE, px); };
    const median = (a) => [...a].sort((x, y) => x - y)[a.length >> 1];
    const nextFrame = () => new Promise((r) => requestAnimationFrame(() => r()));
    const times = v.fieldTimes(v.state.field), t1 = times[times.length - 1];
    // Show every step once, so every step's attribute is on both GPU contexts.
    for (const t of times) { v.setTime(t); v.renderNow(); }
    finish();
    const frame = [], submit = [], sliderJs = [], sliderShown = [];
    for (let i = 0; i < frames; i++) {
      const start = performance.now();
      v.setTime(t1 * i / frames);
      v.renderNow();
      submit.push(performance.now() - start);
      finish();
      frame.push(performance.now() - start);
    }
    // The slider as a user moves it: an 'input' event, then the page's next animation frame.
    const slider = document.getElementById('vv-time');
    for (let i = 0; i < Math.min(frames, 10); i++) {
      const start = performance.now();
      slider.value = String(t1 * ((i * 7) % 10) / 10);
      slider.dispatchEvent(new Event('input'));
      sliderJs.push(performance.now() - start);
      await nextFrame();
      await nextFrame();
      finish();
      sliderShown.push(performance.now() - start);
    }
    // Hover: map point location (CPU) and the 1-pixel 3D pick render + read-back.
    const pick2d = [], pick3d = [];
    const w2 = v.view2d.canvas.clientWidth, h2 = v.view2d.canvas.clientHeight;
    const w3 = v.view3d.canvas.clientWidth, h3 = v.view3d.canvas.clientHeight;
    let hits2d = 0, hits3d = 0;
    for (let i = 0; i < frames; i++) {
      const x = (0.2 + 0.6 * ((i * 7) % frames) / frames), y = (0.2 + 0.6 * i / frames);
      let start = performance.now();
      const [u, w] = v.view2d.toMap(x * w2, y * h2);
      if (v.locator.locate(u, w)) hits2d++;
      pick2d.push(performance.now() - start);
      start = performance.now();
      if (v.view3d.pick(x * w3, y * h3)) hits3d++;
      pick3d.push(performance.now() - start);
    }
    const info = gl.getExtension('WEBGL_debug_renderer_info');
    return { faces: v.nFaces, vertices: v.nVertices, steps: times.length,
      frame_median_ms: median(frame), frame_max_ms: Math.max(...frame), submit_median_ms: median(submit),
      slider_js_median_ms: median(sliderJs), slider_shown_median_ms: median(sliderShown),
      locate2d_median_ms: median(pick2d), pick3d_median_ms: median(pick3d), hits2d, hits3d,
      timings: v.timings, renderer: gl.getParameter(info ? info.UNMASKED_RENDERER_WEBGL : gl.RENDERER) };
  }, Number(opts.frames));
  memory.rss_mb_all_steps = rssMb(profile);
  memory.js_heap_mb_all_steps = await heapMb();
  // The page's own loop while playing: frames drawn per second.
  const play = await page.evaluate(async (seconds) => {
    const v = window.vesselViewer;
    document.getElementById('vv-play').click();
    const start = v.framesDrawn, t = performance.now();
    await new Promise((r) => setTimeout(r, seconds * 1000));
    const fps = (v.framesDrawn - start) / ((performance.now() - t) / 1000);
    document.getElementById('vv-play').click();
    return { play_fps: Math.round(fps * 100) / 100 };
  }, Number(opts['play-seconds']));
  console.log(JSON.stringify({ page: page_path, backend: opts.backend, load_ms: loaded, ...memory, ...result, ...play }));
  if (opts.screenshot) {
    await page.evaluate(() => window.vesselViewer.setTime(0.5));
    await page.evaluate(() => new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(r))));
    await page.screenshot({ path: opts.screenshot });
  }
} finally {
  await browser.close();
}
