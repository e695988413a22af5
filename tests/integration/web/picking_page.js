// Opens a picking job's page (?picking=JOB_ID) in headless chromium and reports, as one JSON line:
// console errors, the page's error text, window.vscanView, what each step draws (window.vscanSeek:
// the parts visible, the part picked, the tool's tip), the step the slider shows after input, how
// playing from the first step went, and a screenshot of the first step.
// usage: node picking_page.js PUPPETEER_CORE_DIR CHROMIUM URL SCREENSHOT_PATH [WIDTHxHEIGHT]
const [puppeteerDir, chromium, url, screenshot, size = '960x540'] = process.argv.slice(2);
const [width, height] = size.split('x').map(Number);
const { shown, withPage } = require('./browser.js');

withPage(puppeteerDir, chromium, url, width, height, async ({ page, consoleErrors }) => {
  const seen = await shown(page);
  await page.screenshot({ path: screenshot });
  const steps = [];
  let slider = null;
  let played = null;
  if (seen.view && seen.view.steps > 0) {
    for (let k = 0; k < seen.view.steps; k += 1) steps.push(await page.evaluate((s) => window.vscanSeek(s), k));
    const last = seen.view.steps - 1;
    slider = await page.evaluate((s) => {
      const input = document.getElementById('step');
      input.value = String(s);
      input.dispatchEvent(new Event('input'));
      return { asked: s, step: window.vscanView.step };
    }, last);
    await page.evaluate(() => window.vscanSeek(0));
    await page.click('#play');
    const playingText = await page.evaluate(() => document.getElementById('play').textContent);
    await page.waitForFunction((n) => window.vscanView.step === n
      && document.getElementById('play').textContent === 'play', { timeout: 60000 }, last);
    played = { playingText, endStep: await page.evaluate(() => window.vscanView.step) };
  }
  console.log(JSON.stringify({ consoleErrors, steps, slider, played, ...seen }));
});
