// The picture a web page draws into its canvas, once the page says it has drawn: headless
// Chromium (the system's, software WebGL) driven by puppeteer-core, for tests/real_clients_test.cpp.
// Usage: node tests/web-screenshot.js PUPPETEER_DIR URL OUT.png WIDTH HEIGHT
//
// Chromium's own --screenshot is taken when the page's virtual time runs out, which decoding a
// glb's images off the main thread does not hold back: a 1.5 MB glb was shot black one time in
// three. Here the page is awaited until it logs "lambert-lightmap: rendered" (or "... error"), and
// the canvas's own pixels are read (toDataURL: the drawing buffer, with no compositor in between).
// Every console line of the page is printed; exit 1 where it did not render within 100 s.
const [puppeteerDir, url, out, width, height] = process.argv.slice(2);
const puppeteer = require(puppeteerDir);
const fs = require('fs');
const { execSync } = require('child_process');

(async () => {
  const browser = await puppeteer.launch({
    executablePath: execSync('command -v chromium', { shell: '/bin/sh' }).toString().trim(),
    headless: true,
    args: ['--no-sandbox', '--disable-gpu', '--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--disable-quic', '--no-first-run',
           '--disable-background-networking', '--disable-component-update', '--disable-sync', '--force-color-profile=srgb',
           '--hide-scrollbars'],
  });
  let status = 1;
  try {
    const page = await browser.newPage();
    await page.setViewport({ width: Number(width), height: Number(height), deviceScaleFactor: 1 });
    const said = new Promise((resolve) => {
      page.on('console', (message) => {
        const text = message.text();
        console.log(`console: ${text}`);
        if (text.startsWith('lambert-lightmap: rendered')) resolve(true);
        if (text.startsWith('lambert-lightmap: error')) resolve(false);
      });
      page.on('pageerror', (error) => { console.log(`page error: ${error.message}`); resolve(false); });
    });
    await page.goto(url);
    const rendered = await Promise.race([said, new Promise((resolve) => setTimeout(() => resolve(false), 100000))]);
    if (rendered) {
      const png = await page.evaluate(() => document.querySelector('canvas').toDataURL('image/png'));
      fs.writeFileSync(out, Buffer.from(png.slice(png.indexOf(',') + 1), 'base64'));
      status = 0;
    } else {
      console.log('web-screenshot: the page did not render');
    }
  } finally {
    await browser.close();
  }
  process.exit(status);
})().catch((error) => {
  console.log(`web-screenshot: ${error.stack ?? error}`);
  process.exit(1);
});
