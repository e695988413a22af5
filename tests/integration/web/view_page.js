// Opens a web view page in headless chromium and reports what a person would see, as one JSON
// line: console errors, the page's error text, where it drew each object, and a PNG screenshot.
// With "pick", it also clicks each object's projected centre and then the page's bottom-right corner,
// reporting what the page picked each time, and takes the screenshot after clicking the first object.
// usage: node view_page.js PUPPETEER_CORE_DIR CHROMIUM URL SCREENSHOT_PATH [WIDTHxHEIGHT [pick]]
const [puppeteerDir, chromium, url, screenshot, size = '320x240', mode = ''] = process.argv.slice(2);
const [width, height] = size.split('x').map(Number);
const { clickAndPick, shown, withPage } = require('./browser.js');

withPage(puppeteerDir, chromium, url, width, height, async ({ page, consoleErrors, requests }) => {
  const seen = await shown(page);
  const picks = [];
  const click = (x, y) => clickAndPick(page, x, y);
  if (mode === 'pick' && seen.view) {
    for (const object of seen.view.objects) picks.push({ at: object.pixel, ...(await click(...object.pixel)) });
    picks.push({ at: [width - 5, height - 5], ...(await click(width - 5, height - 5)) });
    if (seen.view.objects.length > 0) await click(...seen.view.objects[0].pixel);
  }
  await page.screenshot({ path: screenshot });
  console.log(JSON.stringify({ consoleErrors, requests, picks, ...seen }));
});
