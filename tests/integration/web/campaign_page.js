// Opens a job or cloud page of the web view in headless chromium and reports what it showed over
// time, as one JSON line at the end: console errors, requests, window.vscanView sampled every 50 ms
// until the job view's stream closed (or the cloud view was drawn), the clicks asked for and a PNG
// screenshot. Prints "READY" on a line of its own once the page is drawn, so that the caller can
// let the job run from then on.
// usage: node campaign_page.js PUPPETEER_CORE_DIR CHROMIUM URL SCREENSHOT_PATH WIDTHxHEIGHT MODE
//   MODE "job": samples until the stream closes, then clicks each next best view and a point.
//   MODE "cloud": clicks each sample point the page lists, then the bottom-right corner.
//   Any other MODE: only reports what the page shows.
const [puppeteerDir, chromium, url, screenshot, size = '640x480', mode = 'job'] = process.argv.slice(2);
const [width, height] = size.split('x').map(Number);
const { clickAndPick, withPage } = require('./browser.js');

withPage(puppeteerDir, chromium, url, width, height, async ({ page, consoleErrors, requests }) => {
  console.log('READY');
  const samples = [];
  const view = () => page.evaluate(() => (window.vscanView ? JSON.parse(JSON.stringify(window.vscanView)) : null));
  if (mode === 'job') {
    const deadline = Date.now() + 150000;
    for (;;) {
      const seen = await view();
      if (seen) samples.push({ t: Date.now(), shown: seen.shown_points, scans: seen.scans_shown, aligned: seen.aligned_shown });
      if (!seen || seen.stream_closed || Date.now() > deadline) break;
      await new Promise((resolve) => setTimeout(resolve, 50));
    }
  }
  const seen = await view();
  const state = await page.evaluate(() => ({
    errorText: document.getElementById('error').textContent,
    title: document.getElementById('title').textContent,
    text: document.body.innerText,
  }));
  // The screenshot shows the page as drawn, before any click changes the picked box.
  await page.screenshot({ path: screenshot });
  const picks = [];
  const click = (x, y) => clickAndPick(page, x, y);
  if (seen && mode === 'job') {
    for (const view of seen.next_best_views || []) picks.push({ at: view.pixel, ...(await click(...view.pixel)) });
  }
  if (seen && mode === 'cloud') {
    for (const sample of seen.samples) picks.push({ at: sample.pixel, index: sample.index, ...(await click(...sample.pixel)) });
    picks.push({ at: [width - 3, height - 3], ...(await click(width - 3, height - 3)) });
  }
  console.log(JSON.stringify({ consoleErrors, requests, samples, view: seen, picks, ...state }));
});
