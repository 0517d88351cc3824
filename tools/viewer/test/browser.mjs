// Launches Debian's Chromium headless through playwright-core with a fresh profile. WebGL runs
// on SwiftShader (CPU) with --disable-gpu, the default; `gl` asks ANGLE for the system's OpenGL
// (a GPU, or Mesa's llvmpipe) and `vulkan` for Vulkan, which fall back to SwiftShader or no WebGL
// where there is no such driver. close() also removes the profile.
import { chromium } from 'playwright-core';
import { existsSync, mkdtempSync, rmSync } from 'node:fs';
import { join } from 'node:path';

const BACKENDS = {
  swiftshader: ['--disable-gpu', '--use-angle=swiftshader', '--enable-unsafe-swiftshader'],
  gl: ['--use-angle=gl', '--ignore-gpu-blocklist', '--enable-gpu-rasterization'],
  vulkan: ['--use-angle=vulkan', '--enable-features=Vulkan', '--ignore-gpu-blocklist'],
};

export async function launchChromium(executablePath, profileParent, backend = 'swiftshader') {
  if (!existsSync(executablePath))
    throw new Error(`no Chromium at ${executablePath}; run scripts/install-deps.sh (Debian package chromium)`);
  if (!BACKENDS[backend]) throw new Error(`unknown WebGL backend '${backend}'; use ${Object.keys(BACKENDS).join(', ')}`);
  // playwright passes the profile directory as --user-data-dir.
  const profile = mkdtempSync(join(profileParent, 'chromium-profile-'));
  const context = await chromium.launchPersistentContext(profile, {
    executablePath,
    headless: true,
    viewport: { width: 1500, height: 820 },
    args: ['--headless', '--no-sandbox', '--disable-quic', '--no-first-run',
      '--disable-background-networking', '--disable-component-update', '--disable-sync',
      ...BACKENDS[backend]],
  });
  const page = context.pages()[0] || (await context.newPage());
  const close = async () => {
    await context.close();
    rmSync(profile, { recursive: true, force: true });
  };
  return { page, context, profile, close };
}
