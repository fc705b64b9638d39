// A still of a run: a PNG of a .glb (a simulator's --animate) at time t, as
// mbgc-view.html draws it in headless Chromium. For examples' READMEs.
//
//   node build/viewer/still.mjs run.glb out.png [--t 0.5] [--eye x,y,z --target x,y,z]
//        [--fov 40] [--size 800x600] [--flat] [--deform K] [--follow BODY]
//
// eye and target are in the model's world (z up, metres); without them the
// camera frames everything the bodies sweep over the run (or the bodies at
// --t, where their motion dwarfs them; --follow BODY: centred on that body).
// Without --t: the first row. Runs from the build tree (it needs node_modules beside it).
import { writeFileSync } from 'node:fs';
import { fileURLToPath } from 'node:url';
import { parseArgs } from 'node:util';
import { openViewer } from './headless.mjs';

const usage = 'usage: node still.mjs RUN.glb OUT.png [--t SECONDS] [--eye x,y,z --target x,y,z] [--fov DEGREES] [--size WxH] [--flat] [--deform K] [--follow BODY]';
let options;
try {
  options = parseArgs({
    allowPositionals: true,
    options: {
      t: { type: 'string', default: '0' },
      eye: { type: 'string' },
      target: { type: 'string' },
      fov: { type: 'string', default: '40' },
      size: { type: 'string', default: '800x600' },
      flat: { type: 'boolean', default: false },
      deform: { type: 'string' },
      follow: { type: 'string' },
    },
  });
} catch (error) {
  console.error(`${error.message}\n${usage}`);
  process.exit(2);
}
const { values, positionals } = options;
if (positionals.length !== 2) {
  console.error(usage);
  process.exit(2);
}
const [glb, out] = positionals;

const parameters = { t: values.t, fov: values.fov, size: values.size };
if (values.eye) parameters.eye = values.eye;
if (values.target) parameters.target = values.target;
if (values.flat) parameters.flat = '1';
if (values.deform) parameters.deform = values.deform;
if (values.follow) parameters.follow = values.follow;

const viewer = await openViewer({ viewer: fileURLToPath(new URL('./mbgc-view.html', import.meta.url)), glb });
try {
  const picture = await viewer.shot(parameters);
  writeFileSync(out, picture.png);
  console.log(`${out}: ${picture.width}x${picture.height}, t = ${values.t} s`);
} catch (error) {
  console.error(`still.mjs: ${error.message}`);
  process.exitCode = 1;
} finally {
  await viewer.close();
}
