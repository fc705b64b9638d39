// The viewer's browser test: does mbgc-view.html show each body where the
// simulation says it is, at the time asked?
//
// Runs a simulator with --animate and --out (or takes a .glb and .csv
// already written), shows the .glb in the viewer at two times with a fixed
// camera and unlit colours (flat=1), and checks the pictures' pixels: at each
// time, a body's colour is at the pixel where its CSV position projects
// through the camera, and not where the body is at the other time. The
// projection is a plain pinhole camera computed here, independently of
// three.js, from the same eye, target and field of view the viewer is given.
//
//   node check_animation.mjs --viewer-dir BUILD/viewer --work-dir DIR
//        [--sim SIMULATOR] [--glb FILE.glb --csv FILE.csv]
//        --body X_COLUMN,Y_COLUMN,Z_COLUMN=R,G,B ...   (repeatable; colour as the model's BodyVisual::colour, linear RGB 0..1)
//        --times T1,T2 --eye x,y,z --target x,y,z [--fov 40] [--size 480x360]
//        [--tolerance 10] [--centred PX] [--shift-viewer-time DT] [-- SIMULATOR ARGUMENTS]
//
// Positions (CSV columns), eye and target are in the model's world, z up.
// The times must be output rows: between rows the .glb interpolates linearly.
// --centred PX: also, the patch of the body's colour around that pixel has its
// centre within PX pixels of it (for shapes centred on the point the columns
// give: boxes and spheres about their frame's origin). A body seen 30 pixels
// wide passes the first check anywhere within 15 pixels; this one is sharper.
// --shift-viewer-time shows the viewer DT later than the CSV row it is checked
// against: a wrong time on purpose, to see the test fail.
// Exit status: 0 every check passed, 1 a check failed (lines "MISMATCH"),
// 2 the test could not run (bad arguments, the simulator or browser failed).
import { spawnSync } from 'node:child_process';
import { mkdirSync, readFileSync, writeFileSync } from 'node:fs';
import { join } from 'node:path';
import { pathToFileURL } from 'node:url';
import { parseArgs } from 'node:util';

function stop(message) {
  console.error(`error: ${message}`);
  process.exit(2);
}

// ---- arguments ----
let args;
try {
  args = parseArgs({
    allowPositionals: true,
    options: {
      'viewer-dir': { type: 'string' }, 'work-dir': { type: 'string' }, chromium: { type: 'string' },
      sim: { type: 'string' }, glb: { type: 'string' }, csv: { type: 'string' },
      body: { type: 'string', multiple: true }, times: { type: 'string' },
      eye: { type: 'string' }, target: { type: 'string' }, fov: { type: 'string', default: '40' },
      size: { type: 'string', default: '480x360' }, tolerance: { type: 'string', default: '10' }, centred: { type: 'string' },
      'shift-viewer-time': { type: 'string', default: '0' },
    },
  });
} catch (error) {
  stop(error.message);
}
const o = args.values;
for (const required of ['viewer-dir', 'work-dir', 'body', 'times', 'eye', 'target'])
  if (!o[required]) stop(`--${required} is required`);

function numbers(text, count, name) {
  const v = text.split(',').map(Number);
  if (v.length !== count || !v.every(Number.isFinite)) stop(`--${name} ${text}: expected ${count} numbers separated by commas`);
  return v;
}
const times = numbers(o.times, 2, 'times');
const eye = numbers(o.eye, 3, 'eye'), target = numbers(o.target, 3, 'target');
const fov = numbers(o.fov, 1, 'fov')[0], tolerance = numbers(o.tolerance, 1, 'tolerance')[0];
const shift = numbers(o['shift-viewer-time'], 1, 'shift-viewer-time')[0];
const centred = o.centred === undefined ? null : numbers(o.centred, 1, 'centred')[0];
const [width, height] = /^\d+x\d+$/.test(o.size) ? o.size.split('x').map(Number) : stop(`--size ${o.size}: expected WxH`);

/** Linear RGB in 0..1 (as a model gives its colours) to the 8-bit sRGB a screenshot holds. */
const srgb8 = (c) => Math.round(255 * (c <= 0.0031308 ? 12.92 * c : 1.055 * c ** (1 / 2.4) - 0.055));
const bodies = o.body.map((spec) => {
  const m = /^([^=]+)=(.+)$/.exec(spec);
  if (!m) stop(`--body ${spec}: expected X_COLUMN,Y_COLUMN,Z_COLUMN=R,G,B`);
  const columns = m[1].split(',');
  if (columns.length !== 3) stop(`--body ${spec}: expected three CSV columns`);
  return { name: m[1], columns, colour: numbers(m[2], 3, 'body').map(srgb8) };
});

// ---- the run: the simulator writes the .glb and the CSV ----
mkdirSync(o['work-dir'], { recursive: true });
const glb = o.glb ?? join(o['work-dir'], 'run.glb'), csvPath = o.csv ?? join(o['work-dir'], 'run.csv');
if (o.sim) {
  const run = spawnSync(o.sim, ['--animate', glb, '--out', csvPath, ...args.positionals], { stdio: 'inherit' });
  if (run.status !== 0) stop(`${o.sim} exited with ${run.status ?? run.signal}`);
}
const [header, ...rows] = readFileSync(csvPath, 'utf8').trim().split('\n').map((line) => line.split(','));
const column = (name) => {
  const k = header.findIndex((column) => column === name || column.startsWith(`${name} [`));  // `x [m]`
  if (k < 0) stop(`${csvPath} has no column "${name}" (it has ${header.join(', ')})`);
  return k;
};
/** The CSV row at time t: it must be an output row. */
function rowAt(t) {
  const row = rows.find((r) => Math.abs(Number(r[column('t')]) - t) <= 1e-9 * Math.max(1, Math.abs(t)));
  if (!row) stop(`t = ${t} is not an output row of ${csvPath}: between rows the .glb interpolates linearly`);
  return row;
}
const positionAt = (body, t) => body.columns.map((c) => Number(rowAt(t)[column(c)]));

// ---- the camera: a pinhole at eye looking at target, the world's z up the picture ----
const sub = (a, b) => a.map((x, i) => x - b[i]);
const dot = (a, b) => a.reduce((s, x, i) => s + x * b[i], 0);
const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
const unit = (a) => a.map((x) => x / Math.sqrt(dot(a, a)));
const forward = unit(sub(target, eye));
if (Math.abs(forward[2]) > 0.999) stop('the camera looks straight up or down: z cannot be up in the picture');
const right = unit(cross(forward, [0, 0, 1])), up = cross(right, forward);
const focal = height / 2 / Math.tan((fov * Math.PI) / 360);  // pixels per unit of (sideways / depth)
/** Where a world point appears: [x, y] in pixels from the picture's top left corner (pixel [i, j] spans i..i+1, j..j+1). */
function project(p) {
  const d = sub(p, eye), depth = dot(d, forward);
  if (depth <= 0) stop(`the point ${p} is behind the camera`);
  return [width / 2 + (focal * dot(d, right)) / depth, height / 2 - (focal * dot(d, up)) / depth];
}
const pixel = ([x, y]) => [Math.floor(x), Math.floor(y)];

/** The share of pixels in the 5x5 patch around p whose colour is within the tolerance of `colour`. */
function share(picture, [x, y], colour) {
  let hits = 0;
  for (let dy = -2; dy <= 2; ++dy)
    for (let dx = -2; dx <= 2; ++dx) {
      const i = 4 * ((y + dy) * picture.width + (x + dx));
      if ([0, 1, 2].every((k) => Math.abs(picture.rgba[i + k] - colour[k]) <= tolerance)) ++hits;
    }
  return hits / 25;
}
/** The centre of the region of `colour` connected to the 5x5 patch around p (a flood fill): [x, y] like project()'s. */
function blobCentre(picture, [px, py], colour) {
  const seen = new Uint8Array(picture.width * picture.height), stack = [];
  for (let dy = -2; dy <= 2; ++dy) for (let dx = -2; dx <= 2; ++dx) stack.push([px + dx, py + dy]);
  let count = 0, sx = 0, sy = 0;
  while (stack.length) {
    const [x, y] = stack.pop(), k = y * picture.width + x;
    if (x < 0 || y < 0 || x >= picture.width || y >= picture.height || seen[k]) continue;
    seen[k] = 1;
    if (![0, 1, 2].every((c) => Math.abs(picture.rgba[4 * k + c] - colour[c]) <= tolerance)) continue;
    ++count, sx += x + 0.5, sy += y + 0.5;
    stack.push([x + 1, y], [x - 1, y], [x, y + 1], [x, y - 1]);
  }
  return [sx / count, sy / count];
}
const rgbAt = (picture, [x, y]) => `rgb(${Array.from(picture.rgba.subarray(4 * (y * picture.width + x), 4 * (y * picture.width + x) + 3))})`;

// ---- the pictures and the checks ----
const { openViewer } = await import(pathToFileURL(join(o['viewer-dir'], 'headless.mjs')));  // beside node_modules
const viewer = await openViewer({ viewer: join(o['viewer-dir'], 'mbgc-view.html'), glb, chromium: o.chromium });
let failures = 0, checks = 0;
function report(ok, text) {
  ++checks;
  if (!ok) ++failures;
  console.log(`${ok ? 'ok      ' : 'MISMATCH'} ${text}`);
}
try {
  for (const [k, t] of times.entries()) {
    const other = times[1 - k];
    const picture = await viewer.shot({ t: String(t + shift), eye: o.eye, target: o.target, fov: String(fov), size: o.size, flat: '1' });
    if (picture.width !== width || picture.height !== height) stop(`the picture is ${picture.width}x${picture.height}, not ${o.size}`);
    const file = join(o['work-dir'], `view_t${t}.png`);
    writeFileSync(file, picture.png);
    console.log(`t = ${t} s: the viewer at t = ${t + shift} s, ${file}`);
    for (const body of bodies) {
      const exact = project(positionAt(body, t)), here = pixel(exact), there = pixel(project(positionAt(body, other)));
      if (![here, there].every(([x, y]) => x >= 2 && y >= 2 && x < width - 2 && y < height - 2))
        stop(`${body.name} at t = ${t} or ${other} s is outside the picture: choose another camera`);
      if (Math.hypot(here[0] - there[0], here[1] - there[1]) < 20)
        stop(`${body.name} is less than 20 pixels from where it is at t = ${other} s: choose other times or another camera`);
      const expected = `rgb(${body.colour})`;
      const a = share(picture, here, body.colour), b = share(picture, there, body.colour);
      report(a >= 0.5, `  ${body.name} = (${positionAt(body, t)}) at pixel (${here}): ${rgbAt(picture, here)}, ${Math.round(100 * a)} % of the patch ${expected} (needs >= 50 %)`);
      if (centred !== null && a > 0) {
        const centre = blobCentre(picture, here, body.colour), off = Math.hypot(centre[0] - exact[0], centre[1] - exact[1]);
        report(off <= centred, `  its patch of colour is centred at (${centre.map((x) => x.toFixed(1))}), ${off.toFixed(1)} pixels from (${exact.map((x) => x.toFixed(1))}) (needs <= ${centred})`);
      }
      report(b <= 0.1, `  where it is at t = ${other} s, pixel (${there}): ${rgbAt(picture, there)}, ${Math.round(100 * b)} % ${expected} (needs <= 10 %)`);
    }
  }
} catch (error) {
  stop(error.message);
} finally {
  await viewer.close();
}
console.log(`${checks - failures} of ${checks} checks passed`);
process.exit(failures ? 1 : 0);
