// Opens a web view page in headless chromium and reports what a person would see, as one JSON
// line: console errors, the page's error text, where it drew each object, and a PNG screenshot.
// With "pick", it also clicks each object's projected centre and then the page's bottom-right corner,
// reporting what the page picked each time, and takes the screenshot after clicking the first object.
// usage: node view_page.js PUPPETEER_CORE_DIR CHROMIUM URL SCREENSHOT_PATH [WIDTHxHEIGHT [pick]]
const [puppeteerDir, chromium, url, screenshot, size = '320x240', mode = ''] = process.argv.slice(2);
const [width, height] = size.split('x').map(Number);
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
    await page.setViewport({ width, height, deviceScaleFactor: 1 });
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
    const picks = [];
    // Clicks at [x, y] and waits until the page has handled it; returns what the page then shows.
    const click = async (x, y) => {
      const before = await page.evaluate(() => window.vscanPickCount);
      await page.mouse.click(x, y);
      await page.waitForFunction((n) => window.vscanPickCount > n, { timeout: 60000 }, before);
      return page.evaluate(() => ({ picked: window.vscanPicked, panel: document.getElementById('picked').innerText }));
    };
    if (mode === 'pick' && seen.view) {
      for (const object of seen.view.objects) picks.push({ at: object.pixel, ...(await click(...object.pixel)) });
      picks.push({ at: [width - 5, height - 5], ...(await click(width - 5, height - 5)) });
      if (seen.view.objects.length > 0) await click(...seen.view.objects[0].pixel);
    }
    await page.screenshot({ path: screenshot });
    console.log(JSON.stringify({ consoleErrors, requests, picks, ...seen }));
  } finally {
    await browser.close();
  }
})().catch((error) => {
  console.error(error);
  process.exit(1);
});
