// Launches Debian's Chromium headless through playwright-core with a fresh profile; WebGL runs
// on SwiftShader (CPU) since --disable-gpu. close() also removes the profile.
import { chromium } from 'playwright-core';
import { existsSync, mkdtempSync, rmSync } from 'node:fs';
import { join } from 'node:path';

export async function launchChromium(executablePath, profileParent) {
  if (!existsSync(executablePath))
    throw new Error(`no Chromium at ${executablePath}; run scripts/install-deps.sh (Debian package chromium)`);
  // playwright passes the profile directory as --user-data-dir.
  const profile = mkdtempSync(join(profileParent, 'chromium-profile-'));
  const context = await chromium.launchPersistentContext(profile, {
    executablePath,
    headless: true,
    viewport: { width: 1500, height: 820 },
    args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
      '--disable-background-networking', '--disable-component-update', '--disable-sync',
      '--use-angle=swiftshader', '--enable-unsafe-swiftshader'],
  });
  const page = context.pages()[0] || (await context.newPage());
  const close = async () => {
    await context.close();
    rmSync(profile, { recursive: true, force: true });
  };
  return { page, close };
}
