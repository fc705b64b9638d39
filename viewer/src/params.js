// The viewer's URL parameters (mbgc-view.html?file=run.glb&t=0.5&...), read
// and checked. Cameras are given in the model's world, z up, and converted
// here to glTF's axes, y up, in which three.js shows the file.

/**
 * A point of the model's world (x, y, z; z up) in glTF's axes (y up).
 * An --animate file's root node turns the world by -90 degrees about x
 * (runtime/src/animation.cpp), which takes (x, y, z) to (x, z, -y); a camera
 * given in model coordinates goes through the same turn.
 */
export function gltfFromModel([x, y, z]) {
  return [x, z, -y];
}

function numberOf(text, name) {
  const value = Number(text);
  if (text.trim() === '' || !Number.isFinite(value)) throw new Error(`${name}=${text}: expected a number`);
  return value;
}

function vectorOf(text, name) {
  const parts = text.split(',');
  if (parts.length !== 3) throw new Error(`${name}=${text}: expected three numbers x,y,z`);
  return parts.map((part) => numberOf(part, name));
}

/**
 * The parameters of a query string:
 *   file=URL           the .glb to open
 *   t=SECONDS          show that time of the run, paused (default: play from the start)
 *   eye=x,y,z          camera position, model world (z up), metres, at the time first shown
 *   target=x,y,z       the point it looks at (eye and target go together; default: frame the scene:
 *                      everything the bodies sweep over the run, or, where that dwarfs them, the bodies
 *                      at the time shown)
 *   follow=BODY        the camera moves with that body (its node's origin), keeping its offset to it
 *                      while the run plays and while it is orbited; follow=all: the middle of all the
 *                      bodies; follow=none: a fixed camera (default: all where the scene dwarfs the
 *                      bodies, else none)
 *   fov=DEGREES        vertical field of view (default 40)
 *   size=WxH           the picture's size in CSS pixels (default: fill the window)
 *   flat=1             unlit colours, no grid or axes: for pixel tests
 *   speed=X            play X times faster than real time (default 1)
 *   deform=K           draw flexible bodies' deformation K times larger (default 1; the time label says so)
 */
export function parseParameters(search) {
  const query = new URLSearchParams(search);
  const p = { file: query.get('file'), t: null, camera: null, fov: 40, size: null, flat: query.get('flat') === '1', speed: 1, deform: 1,
    follow: query.get('follow') };
  if (p.follow === '') throw new Error('follow=: expected the name of a body, all or none');
  if (query.has('t')) p.t = numberOf(query.get('t'), 't');
  if (query.has('fov')) {
    p.fov = numberOf(query.get('fov'), 'fov');
    if (!(p.fov > 0 && p.fov < 180)) throw new Error(`fov=${p.fov}: expected degrees between 0 and 180`);
  }
  if (query.has('eye') !== query.has('target')) throw new Error('eye= and target= go together');
  if (query.has('eye')) {
    p.camera = {
      eye: gltfFromModel(vectorOf(query.get('eye'), 'eye')),
      target: gltfFromModel(vectorOf(query.get('target'), 'target')),
    };
  }
  if (query.has('size')) {
    const m = /^(\d+)x(\d+)$/.exec(query.get('size'));
    if (!m || +m[1] === 0 || +m[2] === 0) throw new Error(`size=${query.get('size')}: expected WIDTHxHEIGHT in pixels`);
    p.size = [+m[1], +m[2]];
  }
  if (query.has('deform')) {
    p.deform = numberOf(query.get('deform'), 'deform');
    if (!(p.deform > 0)) throw new Error(`deform=${p.deform}: expected a positive number`);
  }
  if (query.has('speed')) {
    p.speed = numberOf(query.get('speed'), 'speed');
    if (!(p.speed > 0)) throw new Error(`speed=${p.speed}: expected a positive number`);
  }
  return p;
}
