// Pictures of mbgc-view.html in headless Chromium: the one path the browser
// test (tests/viewer/check_animation.mjs) and stills (still.mjs) share.
// Runs from the build tree, beside node_modules and mbgc-view.html.
//
// Why puppeteer-core rather than Chromium's own --screenshot flag: the
// viewer draws only after it has fetched and parsed the .glb, and puppeteer
// waits for the page's own flag (window.mbgcReady) instead of a guessed
// delay, reports the page's errors (window.mbgcError, exceptions) as errors
// rather than as a blank picture, and screenshots just the canvas. The
// -core package downloads no browser: it drives the system's Chromium
// (Debian: chromium-headless-shell). pngjs (no dependencies) reads the
// screenshot's pixels.
import http from 'node:http';
import { existsSync, readFile } from 'node:fs';
import puppeteer from 'puppeteer-core';
import { PNG } from 'pngjs';

/** The Chromium to drive: $MBGC_CHROMIUM, else the first one installed. */
export function findChromium() {
  const candidates = [process.env.MBGC_CHROMIUM, '/usr/bin/chromium-headless-shell', '/usr/bin/chromium',
    '/usr/bin/chromium-browser', '/usr/bin/google-chrome'];
  const found = candidates.find((path) => path && existsSync(path));
  if (!found) throw new Error('no Chromium found (Debian: apt-get install chromium-headless-shell; or set MBGC_CHROMIUM)');
  return found;
}

/** An HTTP server on 127.0.0.1 (a free port) serving just these files: {url path: file}. */
function serve(files) {
  const server = http.createServer((request, response) => {
    const file = files[new URL(request.url, 'http://localhost').pathname];
    if (!file) return response.writeHead(404).end();
    readFile(file, (error, data) => {
      if (error) return response.writeHead(404).end();
      const type = file.endsWith('.html') ? 'text/html; charset=utf-8' : 'model/gltf-binary';
      response.writeHead(200, { 'Content-Type': type, 'Cache-Control': 'no-store' }).end(data);
    });
  });
  return new Promise((resolve) => server.listen(0, '127.0.0.1', () => resolve(server)));
}

/**
 * Opens the viewer on a .glb. `shot(parameters, then)` loads the page with
 * those URL parameters (t, eye, target, fov, size, flat, follow:
 * viewer/src/params.js), waits until the frame is drawn, then does what a
 * user would with the controls, in order: `then.follow` chooses that entry
 * of the Follow control, `then.time` moves the time slider there. It returns
 * the canvas as {png, width, height, rgba} (rgba: 4 bytes a pixel, rows from
 * the top) and the page's window.mbgcState() as `state`. close() at the end.
 */
export async function openViewer({ viewer, glb, chromium = findChromium() }) {
  const server = await serve({ '/mbgc-view.html': viewer, '/run.glb': glb });
  const base = `http://127.0.0.1:${server.address().port}`;
  const browser = await puppeteer.launch({
    executablePath: chromium,
    headless: 'shell',
    args: [
      '--no-sandbox',  // it runs as root in containers; it only opens our page and file, from localhost
      '--use-angle=swiftshader', '--enable-unsafe-swiftshader',  // WebGL on the CPU: the same pixels with or without a GPU
      '--hide-scrollbars',
    ],
  });
  return {
    async shot(parameters, then = {}) {
      const page = await browser.newPage();
      const problems = [], notes = [];  // uncaught exceptions; the console's errors, told only if the page fails
      page.on('pageerror', (error) => problems.push(error.message));
      page.on('console', (m) => { if (m.type() === 'error') notes.push(m.text()); });
      const [width, height] = (parameters.size ?? '960x600').split('x').map(Number);
      await page.setViewport({ width: width + 40, height: height + 80, deviceScaleFactor: 1 });
      const query = new URLSearchParams({ file: 'run.glb', ...parameters });
      await page.goto(`${base}/mbgc-view.html?${query}`);
      try {
        await page.waitForFunction('window.mbgcReady || window.mbgcError', { timeout: 60000 });
      } catch (error) {
        throw new Error(`the viewer did not draw within 60 s (${error.message}); ${[...problems, ...notes].join('; ')}`);
      }
      const failure = await page.evaluate(() => window.mbgcError);
      if (failure || problems.length) throw new Error(`the viewer failed: ${[failure, ...problems, ...notes].filter(Boolean).join('; ')}`);
      const control = (id, value, event) => page.evaluate((id, value, event) => {
        const element = document.getElementById(id);
        element.value = value;
        element.dispatchEvent(new Event(event));
        if (element.value !== value && id !== 'slider') throw new Error(`#${id} has no entry ${value}`);
      }, id, value, event);
      if (then.follow !== undefined) await control('follow', String(then.follow), 'change');
      if (then.time !== undefined) await control('slider', String(then.time), 'input');
      // two animation frames: the one the change requested has been drawn
      await page.evaluate(() => new Promise((resolve) => requestAnimationFrame(() => requestAnimationFrame(resolve))));
      const late = await page.evaluate(() => window.mbgcError);
      if (late || problems.length) throw new Error(`the viewer failed: ${[late, ...problems, ...notes].filter(Boolean).join('; ')}`);
      const state = await page.evaluate(() => window.mbgcState());
      const png = Buffer.from(await (await page.$('canvas')).screenshot({ type: 'png' }));
      await page.close();
      const image = PNG.sync.read(png);
      return { png, width: image.width, height: image.height, rgba: image.data, state };
    },
    async close() {
      await browser.close();
      server.close();
    },
  };
}
