// Opens dataset pages of the web view in one headless chromium and reports, per step, what a person
// would see, as one JSON line: console errors, the page's error and text, window.vscanView, and a PNG
// screenshot; then clicks at the step's page pixels (each answered in window.vscanPicked and
// #picked), or follows an in-page link to another view.
// usage: node dataset_page.js PUPPETEER_CORE_DIR CHROMIUM STEPS_JSON
// STEPS_JSON: [{url, size: "WxH", screenshot, clicks: [[x, y], ...], after_clicks_screenshot,
//               follow_view: "N" (a link of #scenes to view N of the shown scene)}]
const fs = require('fs');

const [puppeteerDir, chromium, stepsPath] = process.argv.slice(2);
const steps = JSON.parse(fs.readFileSync(stepsPath, 'utf8'));
const { launch, openPage, clickAndPick, runScript } = require('./browser.js');

runScript(async () => {
  // No GPU is needed (a 2D canvas): no SwiftShader flags.
  const browser = await launch(puppeteerDir, chromium, { webgl: false });
  const results = [];
  try {
    for (const step of steps) {
      const [width, height] = (step.size || '1024x600').split('x').map(Number);
      const { page, consoleErrors, requests } = await openPage(browser, step.url, width, height, { timeout: 30000 });
      const look = () => page.evaluate(() => ({
        view: window.vscanView || null,
        errorText: document.getElementById('error').textContent,
        title: document.getElementById('title').textContent,
        text: document.body.innerText,
        location: location.search,
      }));
      const seen = await look();
      if (step.screenshot) await page.screenshot({ path: step.screenshot });
      const picks = [];
      for (const [x, y] of step.clicks || []) {
        picks.push({ at: [x, y], ...(await clickAndPick(page, x, y, 10000)) });
      }
      if (step.after_clicks_screenshot) await page.screenshot({ path: step.after_clicks_screenshot });
      let followed = null;
      if (step.follow_view !== undefined) {
        const before = await page.evaluate(() => window.vscanDrawCount);
        const links = await page.$$('#scenes a');
        let clicked = false;
        for (const a of links) {
          if ((await a.evaluate((e) => e.textContent)) === String(step.follow_view)) {
            await a.click();
            clicked = true;
            break;
          }
        }
        if (clicked) await page.waitForFunction((n) => window.vscanDrawCount > n, { timeout: 10000 }, before);
        followed = await look();
      }
      results.push({ consoleErrors, requests, picks, followed, ...seen });
      await page.close();
    }
  } finally {
    await browser.close();
  }
  console.log(JSON.stringify(results));
});
