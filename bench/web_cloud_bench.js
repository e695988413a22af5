// The web view's cloud page against a large stored cloud, in headless chromium (WebGL on the CPU,
// SwiftShader): for each run a fresh page (its own browser context) navigates to ?cloud=ID and the
// time from the start of navigation to the first frame drawn is read (performance.now() once the
// page is ready and a pixel of its canvas read back, which waits for the frame); then the view is turned with the orbit controls, frame by frame
// (controls.update() renders; reading back one pixel waits for the frame to be drawn), and the
// frame rate read: once as a drag turns it (the controls' 'start' event first: the page then draws
// its turning budget of points) and once drawing every point.
// Prints one JSON line: {"first_frame_ms": [...], "raf_after_first_render_ms": [...], "rotate_fps": [...],
// "rotate_fps_all_points": [...], "points_while_turning": N, "points": N}.
// usage: node web_cloud_bench.js PUPPETEER_CORE_DIR CHROMIUM URL [RUNS [FRAMES [WIDTHxHEIGHT]]]
const [puppeteerDir, chromium, url, runs = '5', frames = '60', size = '1280x720'] = process.argv.slice(2);
const [width, height] = size.split('x').map(Number);
const { launch, openPage, runScript } = require('../tests/integration/web/browser.js');

runScript(async () => {
  const browser = await launch(puppeteerDir, chromium);
  const result = {
    first_frame_ms: [], raf_after_first_render_ms: [], rotate_fps: [], rotate_fps_all_points: [], points: 0,
    points_while_turning: 0, errors: [],
  };
  try {
    for (let run = 0; run < Number(runs); run += 1) {
      const context = await browser.createBrowserContext();
      const { page } = await openPage(context, url, width, height,
        { timeout: 300000, polling: 10, consoleErrors: result.errors });
      const first = await page.evaluate(() => {
        const gl = window.vscanViewer.renderer.getContext();
        gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, new Uint8Array(4));
        return { at: performance.now(), points: window.vscanView.shown_points };
      });
      await page.waitForFunction('window.vscanFirstFrame !== undefined', { timeout: 300000, polling: 10 });
      result.first_frame_ms.push(first.at);
      result.raf_after_first_render_ms.push(await page.evaluate(() => window.vscanFirstFrame));
      result.points = first.points;
      const turn = (count, dragging) => page.evaluate((frameCount, drag) => {
        const viewer = window.vscanViewer;
        const { controls, camera } = viewer;
        if (drag) controls.dispatchEvent({ type: 'start' });
        const gl = viewer.renderer.getContext();
        const [c, s] = [Math.cos(2 * Math.PI / frameCount), Math.sin(2 * Math.PI / frameCount)];
        const pixel = new Uint8Array(4);
        const framesBefore = viewer.frames;
        const start = performance.now();
        for (let i = 0; i < frameCount; i += 1) {
          // One step of a full turn about the target's vertical (z up), as a drag would make.
          const x = camera.position.x - controls.target.x;
          const y = camera.position.y - controls.target.y;
          camera.position.x = controls.target.x + c * x - s * y;
          camera.position.y = controls.target.y + s * x + c * y;
          controls.update();  // emits 'change': the page draws the frame
          gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, pixel);
        }
        const seconds = (performance.now() - start) / 1000;
        const drawn = viewer.pointsDrawn;
        if (drag) controls.dispatchEvent({ type: 'end' });
        if (viewer.frames - framesBefore !== frameCount + (drag ? 1 : 0)) {
          throw new Error(`${viewer.frames - framesBefore} frames drawn of ${frameCount}`);
        }
        return { fps: frameCount / seconds, drawn };
      }, count, dragging);
      const turning = await turn(Number(frames), true);
      result.rotate_fps.push(turning.fps);
      result.points_while_turning = turning.drawn;
      result.rotate_fps_all_points.push((await turn(Number(frames), false)).fps);
      await context.close();
    }
  } finally {
    await browser.close();
  }
  console.log(JSON.stringify(result));
});
