// Measures a generated page in headless Chromium: load time (decode + first frame) and the time
// per animation frame (time step change + both views rendered and finished). Not a test: with
// --disable-gpu the figures are SwiftShader's (CPU) ones, far slower than any real GPU.
//   node test/perf.mjs PAGE.html [--chromium /usr/bin/chromium] [--frames 30] [--screenshot PNG]
import { tmpdir } from 'node:os';
import { resolve } from 'node:path';
import { pathToFileURL } from 'node:url';
import { launchChromium } from './browser.mjs';

const [page_path, ...rest] = process.argv.slice(2);
const opts = { chromium: '/usr/bin/chromium', frames: '30' };
for (let i = 0; i < rest.length; i += 2) opts[rest[i].replace(/^--/, '')] = rest[i + 1];
const browser = await launchChromium(opts.chromium, tmpdir());
try {
  const { page } = browser;
  const t0 = Date.now();
  await page.goto(pathToFileURL(resolve(page_path)).href);
  await page.waitForFunction(() => document.body.dataset.ready || document.body.dataset.error, null, { timeout: 300000 });
  const loaded = Date.now() - t0;
  const result = await page.evaluate((frames) => {
    const v = window.vesselViewer;
    const gl = v.view2d.renderer.getContext(), gl3 = v.view3d.renderer.getContext();
    const px = new Uint8Array(4);
    const median = (a) => a.sort((x, y) => x - y)[a.length >> 1];
    const times = [], submit = [], pick2d = [], pick3d = [];
    for (let i = 0; i < frames; i++) {
      const start = performance.now();
      v.setTime(1.8 * i / frames);
      v.renderNow();
      submit.push(performance.now() - start);
      gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, px); // waits for the frame
      gl3.readPixels(0, 0, 1, 1, gl3.RGBA, gl3.UNSIGNED_BYTE, px);
      times.push(performance.now() - start);
    }
    // Hover: map point location (CPU) and the 1-pixel 3D pick render + read-back.
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
    return { faces: v.nFaces, frame_median_ms: median(times), frame_max_ms: Math.max(...times),
      submit_median_ms: median(submit), locate2d_median_ms: median(pick2d), pick3d_median_ms: median(pick3d),
      hits2d, hits3d, timings: v.timings,
      renderer: gl.getParameter(gl.getExtension('WEBGL_debug_renderer_info')?.UNMASKED_RENDERER_WEBGL ?? gl.RENDERER) };
  }, Number(opts.frames));
  console.log(JSON.stringify({ page: page_path, load_ms: loaded, ...result }));
  if (opts.screenshot) {
    await page.evaluate(() => window.vesselViewer.setTime(0.5));
    await page.evaluate(() => new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(r))));
    await page.screenshot({ path: opts.screenshot });
  }
} finally {
  await browser.close();
}
