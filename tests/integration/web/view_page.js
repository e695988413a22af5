// Opens a web view page in headless chromium and reports what a person would see, as one JSON
// line: console errors, the page's error text, where it drew each object, and a PNG screenshot.
// usage: node view_page.js PUPPETEER_CORE_DIR CHROMIUM URL SCREENSHOT_PATH
const [puppeteerDir, chromium, url, screenshot] = process.argv.slice(2);
const puppeteer = require(puppeteerDir);

(async () => {
  const browser = await puppeteer.launch({
    executablePath: chromium,
    headless: true,
    // WebGL without a GPU: SwiftShader through ANGLE, asked for explicitly (chromium 156 falls back
    // to it by itself, older and newer ones may need the flags). No sandbox: tests may run as root.
    // Shared memory in /tmp: containers often give /dev/shm only 64 MiB.
    args: ['--no-sandbox', '--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--ignore-gpu-blocklist',
      '--disable-dev-shm-usage'],
  });
  try {
    const page = await browser.newPage();
    await page.setViewport({ width: 320, height: 240, deviceScaleFactor: 1 });
    const consoleErrors = [];
    const requests = [];
    page.on('request', (request) => requests.push(request.url()));
    page.on('console', (message) => {
      if (message.type() === 'error') consoleErrors.push(message.text());
    });
    page.on('pageerror', (error) => consoleErrors.push(String(error)));
    await page.goto(url, { waitUntil: 'load', timeout: 60000 });
    await page.waitForFunction('window.vscanReady === true', { timeout: 60000 });
    const seen = await page.evaluate(() => ({
      view: window.vscanView || null,
      errorText: document.getElementById('error').textContent,
      title: document.getElementById('title').textContent,
      text: document.body.innerText,
    }));
    await page.screenshot({ path: screenshot });
    console.log(JSON.stringify({ consoleErrors, requests, ...seen }));
  } finally {
    await browser.close();
  }
})().catch((error) => {
  console.error(error);
  process.exit(1);
});
