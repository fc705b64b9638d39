// The viewer's browser test of what frames the picture: following a body,
// the drawn surfaces and the grid. Runs a simulator with --animate (or takes a .glb), opens
// it in mbgc-view.html (headless Chromium, unlit colours: flat=1) and checks
// the page's state (window.mbgcState: camera, bodies, surfaces, grid, model world)
// and the pictures' pixels.
//
//   node check_scene.mjs --viewer-dir BUILD/viewer --work-dir DIR [--chromium PATH]
//        [--sim SIMULATOR | --glb FILE.glb] [--size 480x360]
//        [--follow BODY=R,G,B --times T0,T1 [--min-share S] [--follow-param VALUE]]
//        [--surface NAME@x,y,z=R,G,B ... --at T --eye x,y,z --target x,y,z [--fov 40] [--shift-surfaces dx,dy,dz]]
//        [--grid D [--at T]] [--tolerance 10] [-- SIMULATOR ARGUMENTS]
//
// --follow: the body (its colour as the model's BodyVisual::colour, linear RGB):
//   1. the default view at T0 (no camera given) shows the body at least S of
//      the picture (--min-share: a vehicle at its own size, not a dot on its
//      trajectory);
//   2. with follow=BODY, moving the time slider from T0 to T1 keeps the
//      camera's offset to the body (eye - body and target - body the same),
//      and the body's colour stays at the middle of the picture, where the
//      default framing with follow puts it;
//   3. with follow=none and the camera of 2 at T0, the same slider move
//      leaves the camera where it was, and the body is gone from the middle
//      (the body moved: following is what kept it there);
//   4. with follow=none, then the Follow control set to BODY (a user's
//      choice), the slider to T1: the body is at the middle again.
//   --follow-param VALUE gives follow=VALUE in 2 instead: a mistake (none)
//   the test must catch.
// --surface: at time T (--at) with the fixed camera, the surface NAME is one
//   of the file's surfaces (not a body), and its colour is at the pixel where
//   the point x,y,z (model world, on or inside the surface) projects; the
//   projection is a pinhole camera computed here, independently of three.js.
//   --shift-surfaces moves every checked point: a mistake the test must catch.
// --grid D: the default view at time T (--at, default 0; no camera given,
//   the grid drawn: flat=0) is of the bodies' size D (metres): the grid lies
//   below every body's origin and at most D below the lowest, and the camera
//   is at most 10 D from what it looks at. (The mistake: a box that holds a
//   flexible body's morph targets at full weight, metres for a beam of
//   centimetres, puts the grid out of sight below it.)
// Exit status: 0 every check passed, 1 a check failed (lines "MISMATCH"),
// 2 the test could not run.
import { spawnSync } from 'node:child_process';
import { mkdirSync, writeFileSync } from 'node:fs';
import { join } from 'node:path';
import { pathToFileURL } from 'node:url';
import { parseArgs } from 'node:util';

function stop(message) {
  console.error(`error: ${message}`);
  process.exit(2);
}

let args;
try {
  args = parseArgs({
    allowPositionals: true,
    options: {
      'viewer-dir': { type: 'string' }, 'work-dir': { type: 'string' }, chromium: { type: 'string' },
      sim: { type: 'string' }, glb: { type: 'string' }, size: { type: 'string', default: '480x360' },
      follow: { type: 'string' }, times: { type: 'string' }, 'min-share': { type: 'string', default: '0' },
      'follow-param': { type: 'string' },
      surface: { type: 'string', multiple: true }, at: { type: 'string' }, eye: { type: 'string' }, target: { type: 'string' },
      fov: { type: 'string', default: '40' }, 'shift-surfaces': { type: 'string', default: '0,0,0' },
      tolerance: { type: 'string', default: '10' }, grid: { type: 'string' },
    },
  });
} catch (error) {
  stop(error.message);
}
const o = args.values;
for (const required of ['viewer-dir', 'work-dir']) if (!o[required]) stop(`--${required} is required`);
if (!o.follow && !o.surface && !o.grid) stop('nothing to check: give --follow, --surface or --grid');

function numbers(text, count, name) {
  const v = String(text).split(',').map(Number);
  if (v.length !== count || !v.every(Number.isFinite)) stop(`--${name} ${text}: expected ${count} numbers separated by commas`);
  return v;
}
const [width, height] = /^\d+x\d+$/.test(o.size) ? o.size.split('x').map(Number) : stop(`--size ${o.size}: expected WxH`);
const tolerance = numbers(o.tolerance, 1, 'tolerance')[0];
/** Linear RGB in 0..1 (as a model gives its colours) to the 8-bit sRGB a screenshot holds. */
const srgb8 = (c) => Math.round(255 * (c <= 0.0031308 ? 12.92 * c : 1.055 * c ** (1 / 2.4) - 0.055));
const colourOf = (text, name) => numbers(text, 3, name).map(srgb8);

// ---- the run ----
mkdirSync(o['work-dir'], { recursive: true });
const glb = o.glb ?? join(o['work-dir'], 'run.glb');
if (o.sim) {
  const run = spawnSync(o.sim, ['--animate', glb, ...args.positionals], { stdio: 'inherit' });
  if (run.status !== 0) stop(`${o.sim} exited with ${run.status ?? run.signal}`);
}

// ---- pixels ----
/** The share of pixels in the 5x5 patch around [x, y] whose colour is within the tolerance of `colour`. */
function share(picture, [x, y], colour) {
  let hits = 0;
  for (let dy = -2; dy <= 2; ++dy)
    for (let dx = -2; dx <= 2; ++dx) {
      const i = 4 * ((y + dy) * picture.width + (x + dx));
      if ([0, 1, 2].every((k) => Math.abs(picture.rgba[i + k] - colour[k]) <= tolerance)) ++hits;
    }
  return hits / 25;
}
/** The share of the whole picture in `colour`. */
function coverage(picture, colour) {
  let hits = 0;
  for (let i = 0; i < picture.rgba.length; i += 4)
    if ([0, 1, 2].every((k) => Math.abs(picture.rgba[i + k] - colour[k]) <= tolerance)) ++hits;
  return hits / (picture.width * picture.height);
}
const rgbAt = (picture, [x, y]) => `rgb(${Array.from(picture.rgba.subarray(4 * (y * picture.width + x), 4 * (y * picture.width + x) + 3))})`;
const middle = [Math.floor(width / 2), Math.floor(height / 2)];

// ---- vectors ----
const sub = (a, b) => a.map((x, i) => x - b[i]);
const dot = (a, b) => a.reduce((s, x, i) => s + x * b[i], 0);
const norm = (a) => Math.sqrt(dot(a, a));
const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
const unit = (a) => a.map((x) => x / norm(a));
const fmt = (v) => `(${v.map((x) => x.toFixed(3)).join(', ')})`;

const { openViewer } = await import(pathToFileURL(join(o['viewer-dir'], 'headless.mjs')));  // beside node_modules
const viewer = await openViewer({ viewer: join(o['viewer-dir'], 'mbgc-view.html'), glb, chromium: o.chromium });
let failures = 0, checks = 0;
function report(ok, text) {
  ++checks;
  if (!ok) ++failures;
  console.log(`${ok ? 'ok      ' : 'MISMATCH'} ${text}`);
}
async function shot(name, parameters, then = {}) {
  const picture = await viewer.shot({ size: o.size, flat: '1', ...parameters }, then);
  if (picture.width !== width || picture.height !== height) stop(`the picture is ${picture.width}x${picture.height}, not ${o.size}`);
  const file = join(o['work-dir'], `${name}.png`);
  writeFileSync(file, picture.png);
  console.log(`${name}: ${new URLSearchParams(parameters)}${Object.keys(then).length ? `, then ${JSON.stringify(then)}` : ''} (${file})`);
  return picture;
}

try {
  if (o.follow) {
    const m = /^([^=]+)=(.+)$/.exec(o.follow);
    if (!m) stop(`--follow ${o.follow}: expected BODY=R,G,B`);
    const [body, colour] = [m[1], colourOf(m[2], 'follow')];
    if (!o.times) stop('--follow needs --times T0,T1');
    const [t0, t1] = numbers(o.times, 2, 'times');
    const minShare = numbers(o['min-share'], 1, 'min-share')[0];
    const at = (state) => {
      if (!state.bodies[body]) stop(`the file has no body ${body} (it has ${Object.keys(state.bodies).join(', ')})`);
      return state.bodies[body];
    };

    // 1. the default view
    const plain = await shot('default', { t: String(t0) });
    const seen = coverage(plain, colour);
    report(seen >= minShare, `default view at t = ${t0} s (follow=${plain.state.follow}): ${body} covers ${(100 * seen).toFixed(2)} % of the picture (needs >= ${100 * minShare} %)`);

    // 2. following: the slider from t0 to t1
    const follow = o['follow-param'] ?? body;
    const start = await shot('follow_t0', { t: String(t0), follow });
    const moved = await shot('follow_t1', { t: String(t0), follow }, { time: t1 });
    const travel = norm(sub(at(moved.state), at(start.state)));
    const offset0 = sub(start.state.eye, at(start.state)), offset1 = sub(moved.state.eye, at(moved.state));
    if (travel < norm(offset0)) stop(`${body} moves ${travel.toFixed(3)} m from t = ${t0} to ${t1} s, less than the camera's distance: choose other times`);
    const slack = 1e-6 * Math.max(norm(offset0), travel);
    report(norm(sub(offset1, offset0)) <= slack && norm(sub(sub(moved.state.target, at(moved.state)), sub(start.state.target, at(start.state)))) <= slack,
      `follow=${follow}: ${body} travels ${travel.toFixed(3)} m from t = ${t0} to ${t1} s; the eye's offset to it ${fmt(offset0)} -> ${fmt(offset1)} (must stay)`);
    for (const [picture, t] of [[start, t0], [moved, t1]]) {
      const a = share(picture, middle, colour);
      report(a >= 0.5, `follow=${follow} at t = ${t} s: the middle of the picture ${rgbAt(picture, middle)}, ${Math.round(100 * a)} % ${body}'s rgb(${colour}) (needs >= 50 %)`);
    }

    // 3. not following: the same camera at t0, the same slider move
    const camera = { eye: start.state.eye.join(','), target: start.state.target.join(',') };
    const still = await shot('fixed_t1', { t: String(t0), follow: 'none', ...camera }, { time: t1 });
    report(norm(sub(still.state.eye, start.state.eye)) <= slack, `follow=none: the eye stays at ${fmt(start.state.eye)}: ${fmt(still.state.eye)}`);
    const left = share(still, middle, colour);
    report(left <= 0.1, `follow=none at t = ${t1} s: the middle of the picture ${rgbAt(still, middle)}, ${Math.round(100 * left)} % ${body}'s colour (needs <= 10 %: it drove on)`);

    // 4. the Follow control
    const chosen = await shot('control_t1', { t: String(t0), follow: 'none', ...camera }, { follow: body, time: t1 });
    const back = share(chosen, middle, colour);
    report(chosen.state.follow === body && back >= 0.5,
      `Follow control set to ${body} (it shows ${chosen.state.follow}), then t = ${t1} s: the middle ${rgbAt(chosen, middle)}, ${Math.round(100 * back)} % ${body}'s colour (needs >= 50 %)`);
  }

  if (o.surface) {
    for (const required of ['at', 'eye', 'target']) if (!o[required]) stop(`--surface needs --${required}`);
    const t = numbers(o.at, 1, 'at')[0], eye = numbers(o.eye, 3, 'eye'), target = numbers(o.target, 3, 'target');
    const fov = numbers(o.fov, 1, 'fov')[0], shift = numbers(o['shift-surfaces'], 3, 'shift-surfaces');
    // the camera: a pinhole at eye looking at target, the world's z up the picture
    const forward = unit(sub(target, eye));
    if (Math.abs(forward[2]) > 0.999) stop('the camera looks straight up or down: z cannot be up in the picture');
    const right = unit(cross(forward, [0, 0, 1])), up = cross(right, forward);
    const focal = height / 2 / Math.tan((fov * Math.PI) / 360);
    const project = (p) => {
      const d = sub(p, eye), depth = dot(d, forward);
      if (depth <= 0) stop(`the point ${p} is behind the camera`);
      return [Math.floor(width / 2 + (focal * dot(d, right)) / depth), Math.floor(height / 2 - (focal * dot(d, up)) / depth)];
    };
    const picture = await shot('surfaces', { t: String(t), eye: o.eye, target: o.target, fov: String(fov), follow: 'none' });
    const names = Object.keys(picture.state.surfaces);
    console.log(`surfaces in the file: ${names.map((n) => `${n} (${picture.state.surfaces[n]})`).join(', ') || 'none'}`);
    for (const spec of o.surface) {
      const m = /^([^@]+)@([^=]+)=(.+)$/.exec(spec);
      if (!m) stop(`--surface ${spec}: expected NAME@x,y,z=R,G,B`);
      const [name, point, colour] = [m[1], numbers(m[2], 3, 'surface').map((x, i) => x + shift[i]), colourOf(m[3], 'surface')];
      report(name in picture.state.surfaces && !(name in picture.state.bodies),
        `${name} is a surface of the file (${picture.state.surfaces[name] ?? 'missing'}), not a body`);
      const here = project(point);
      if (!(here[0] >= 2 && here[1] >= 2 && here[0] < width - 2 && here[1] < height - 2))
        stop(`${name}'s point ${point} is outside the picture: choose another camera`);
      const a = share(picture, here, colour);
      report(a >= 0.5, `  at ${fmt(point)}, pixel (${here}): ${rgbAt(picture, here)}, ${Math.round(100 * a)} % its rgb(${colour}) (needs >= 50 %)`);
    }
  }

  if (o.grid) {
    const size = numbers(o.grid, 1, 'grid')[0], t = numbers(o.at ?? '0', 1, 'at')[0];
    const picture = await shot('grid', { t: String(t), flat: '0' });
    const { grid, bodies, eye, target } = picture.state;
    if (grid === null) stop('the viewer drew no grid');
    const lowest = Math.min(...Object.values(bodies).map((p) => p[2]));
    report(grid <= lowest && grid >= lowest - size,
      `default view at t = ${t} s: the grid at z = ${grid.toFixed(4)} m, the bodies' lowest origin at ${lowest.toFixed(4)} m (needs the grid below it by at most ${size} m)`);
    const distance = norm(sub(eye, target));
    report(distance <= 10 * size, `  the camera ${distance.toFixed(4)} m from its target (needs <= ${10 * size} m)`);
  }
} catch (error) {
  stop(error.message);
} finally {
  await viewer.close();
}
console.log(`${checks - failures} of ${checks} checks passed`);
process.exit(failures ? 1 : 0);
