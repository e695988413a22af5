// Headless chromium for the web view's page scripts and the cloud bench: one launch, and pages opened
// the same way (viewport, console errors and page errors collected, requests recorded, loaded until
// the page sets window.vscanReady).

// WebGL without a GPU: SwiftShader through ANGLE, asked for explicitly (chromium 156 falls back to it
// by itself, older and newer ones may need the flags). No sandbox: tests may run as root. Shared
// memory in /tmp: containers often give /dev/shm only 64 MiB.
const WEBGL_ARGS = ['--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--ignore-gpu-blocklist'];

// The browser at CHROMIUM through the puppeteer-core at PUPPETEER_DIR; { webgl: false } leaves out
// the SwiftShader flags (pages that draw only on a 2D canvas).
function launch(puppeteerDir, chromium, { webgl = true } = {}) {
  const puppeteer = require(puppeteerDir);
  return puppeteer.launch({
    executablePath: chromium,
    headless: true,
    args: ['--no-sandbox', ...(webgl ? WEBGL_ARGS : []), '--disable-dev-shm-usage'],
  });
}

// A new page of BROWSER (or of a browser context) at WIDTH x HEIGHT, loaded from URL and ready.
// Options: timeout (ms, for the load and for ready), polling (of window.vscanReady), and the arrays
// consoleErrors and requests to collect into. Returns { page, consoleErrors, requests }.
async function openPage(browser, url, width, height, options = {}) {
  const { timeout = 60000, polling, consoleErrors = [], requests = [] } = options;
  const page = await browser.newPage();
  await page.setViewport({ width, height, deviceScaleFactor: 1 });
  page.on('request', (request) => requests.push(request.url()));
  page.on('console', (message) => {
    if (message.type() === 'error') consoleErrors.push(message.text());
  });
  page.on('pageerror', (error) => consoleErrors.push(String(error)));
  await page.goto(url, { waitUntil: 'load', timeout });
  await page.waitForFunction('window.vscanReady === true', polling === undefined ? { timeout } : { timeout, polling });
  return { page, consoleErrors, requests };
}

// Clicks PAGE at (x, y), waits until the page has handled the click (window.vscanPickCount), and
// returns what it then shows: { picked: window.vscanPicked, panel: the text of #picked }.
async function clickAndPick(page, x, y, timeout = 60000) {
  const before = await page.evaluate(() => window.vscanPickCount);
  await page.mouse.click(x, y);
  await page.waitForFunction((n) => window.vscanPickCount > n, { timeout }, before);
  return page.evaluate(() => ({ picked: window.vscanPicked, panel: document.getElementById('picked').innerText }));
}

// What the page shows: window.vscanView (null before a view is drawn), the error line, the title and
// the text of the whole page.
function shown(page) {
  return page.evaluate(() => ({
    view: window.vscanView || null,
    errorText: document.getElementById('error').textContent,
    title: document.getElementById('title').textContent,
    text: document.body.innerText,
  }));
}

// Runs MAIN (an async function) and exits with status 1 on any error, which goes to stderr.
function runScript(main) {
  main().catch((error) => {
    console.error(error);
    process.exit(1);
  });
}

// Runs BODY({ page, consoleErrors, requests }) on one page opened with openPage in a browser started
// with launch, then closes the browser; exits with status 1 on any error.
function withPage(puppeteerDir, chromium, url, width, height, body) {
  runScript(async () => {
    const browser = await launch(puppeteerDir, chromium);
    try {
      await body(await openPage(browser, url, width, height));
    } finally {
      await browser.close();
    }
  });
}

module.exports = { launch, openPage, clickAndPick, shown, runScript, withPage };
