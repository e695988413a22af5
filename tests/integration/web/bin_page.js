// Opens a bin fill's page (?bin=JOB_ID) in headless chromium and reports, as one JSON line: console
// errors, the page's error text, window.vscanView at the final pile, a screenshot of it (before any
// click), what the page picked on a click at each part's projected centre, the parts' centres at the
// replay's first and last frames (window.vscanSeek), the frame the slider shows, how playing from the
// start went, and a second screenshot after clicking the first part.
// usage: node bin_page.js PUPPETEER_CORE_DIR CHROMIUM URL SCREENSHOT_PATH PICKED_SCREENSHOT_PATH [WIDTHxHEIGHT]
const [puppeteerDir, chromium, url, screenshot, pickedShot, size = '960x540'] = process.argv.slice(2);
const [width, height] = size.split('x').map(Number);
const { clickAndPick, shown, withPage } = require('./browser.js');

withPage(puppeteerDir, chromium, url, width, height, async ({ page, consoleErrors, requests }) => {
  const seen = {
    ...(await shown(page)),
    sceneLink: await page.evaluate(() => {
      const link = document.getElementById('scene-link');
      return link ? link.href : null;
    }),
  };
  await page.screenshot({ path: screenshot });
  const click = (x, y) => clickAndPick(page, x, y);
  const picks = [];
  let first = null;
  let last = null;
  let slider = null;
  let played = null;
  if (seen.view && seen.view.parts) {
    for (const part of seen.view.parts) {
      if (part.pixel) picks.push({ at: part.pixel, ...(await click(...part.pixel)) });
    }
    if (seen.view.frames > 0) {
      first = await page.evaluate(() => window.vscanSeek(0));
      last = await page.evaluate((n) => window.vscanSeek(n - 1), seen.view.frames);
      // The slider: the middle frame, as a person would drag it.
      const middle = Math.floor(seen.view.frames / 2);
      slider = await page.evaluate((f) => {
        const input = document.getElementById('frame');
        input.value = String(f);
        input.dispatchEvent(new Event('input'));
        return { asked: f, frame: window.vscanView.frame };
      }, middle);
      // Play from the start: the frames advance in simulated time up to the last, where it stops.
      await page.evaluate(() => window.vscanSeek(0));
      const started = Date.now();
      await page.click('#play');
      const playingText = await page.evaluate(() => document.getElementById('play').textContent);
      await page.waitForFunction((n) => window.vscanView.frame === n - 1, { timeout: 60000 }, seen.view.frames);
      played = { playingText, seconds: (Date.now() - started) / 1000,
        endText: await page.evaluate(() => document.getElementById('play').textContent) };
    }
    const shown = seen.view.parts.find((p) => p.pixel);
    if (shown) await click(...shown.pixel);
  }
  await page.screenshot({ path: pickedShot });
  console.log(JSON.stringify({ consoleErrors, requests, picks, first, last, slider, played, ...seen }));
});
