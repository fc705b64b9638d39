// mbgc-view: plays the motion a simulator writes with --animate FILE.glb
// (runtime/src/animation.cpp: a node per body, one animation sampled at the
// output rows, a flexible body's modes as morph weights).
//
// The viewer owns the clock: `time` is the run's time in seconds, and the
// AnimationMixer only evaluates the file's tracks at it (showAt), so a
// paused view, the slider and playback all show exactly the keyframes'
// linear interpolation at `time`, never a time the mixer wrapped round or
// stopped at (AnimationAction loops and clamps on its own otherwise).
//
// The camera may follow a body (follow=BODY, or the Follow control): every
// time the run is posed, camera and orbit target move by as much as the body
// did, so the view keeps its offset to it whether the run plays, the slider
// moves or the user orbits. Surfaces (nodes the runtime marks
// extras.surface: contact surfaces, roads) are drawn but neither framed nor
// followed.
//
// For tests and stills (viewer/headless.mjs): URL parameters (params.js) fix
// the time and the camera, and once the frame at that time is on screen the
// page sets window.mbgcReady = true (or window.mbgcError to a message);
// window.mbgcState() tells the camera, the bodies, the surfaces and the grid.
import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';
import { parseParameters } from './params.js';
import { boxOf, sweptBox, largest, dwarfs, centredOn, frameBox, helpers } from './framing.js';

const $ = (id) => document.getElementById(id);
const view = $('view'), message = $('message'), playButton = $('play'), slider = $('slider'), followSelect = $('follow');

function fail(text) {
  message.textContent = text;
  message.className = 'error';
  message.hidden = false;
  window.mbgcError = text;
  console.error(`mbgc-view: ${text}`);
}

let params;
try {
  params = parseParameters(location.search);
} catch (e) {
  params = parseParameters('');
  fail(e.message);
}

// ---- the scene: a light background, soft light from above and a sun ----
const renderer = new THREE.WebGLRenderer({ antialias: true });
renderer.setPixelRatio(window.devicePixelRatio);
view.prepend(renderer.domElement);
const scene = new THREE.Scene();
scene.background = new THREE.Color(0xf5f5f2);
scene.add(new THREE.HemisphereLight(0xffffff, 0x8c8c84, 1.6));  // sky, ground
const sun = new THREE.DirectionalLight(0xffffff, 1.4);
sun.position.set(2, 4, 3);  // glTF axes: from above (y), the front (z) and the right (x)
scene.add(sun);
const camera = new THREE.PerspectiveCamera(params.fov, 1, 0.01, 100);
const controls = new OrbitControls(camera, renderer.domElement);
controls.addEventListener('change', requestRender);

if (params.size) {
  view.classList.add('fixed');
  view.style.width = `${params.size[0]}px`;
  view.style.height = `${params.size[1]}px`;
}
function resize() {
  const [w, h] = params.size ?? [view.clientWidth, view.clientHeight];
  renderer.setSize(w, h);
  camera.aspect = w / h;
  camera.updateProjectionMatrix();
  requestRender();
}
window.addEventListener('resize', resize);

// ---- the loaded run ----
let model = null, extras = null, mixer = null, action = null, scale = null;
let tStart = 0, tEnd = 0, time = 0, playing = false, lastFrame = null;
let bodies = [], surfaces = [];          // the file's body nodes; its surface nodes
let followed = null, lastFollowed = null;  // null, 'all' or a body node; where it was when last posed
let frameRequested = false, ready = false;  // a frame is due; the next one drawn is a new run's first

/** Poses the model at run time t (clamped to the keyframes' span). */
function showAt(t) {
  time = Math.min(Math.max(t, tStart), tEnd);
  if (action) {
    action.time = time;
    mixer.update(0);  // evaluate the tracks at action.time, no time step
    if (params.deform !== 1)  // the modal coordinates, scaled: a small deflection made visible
      model.traverse((o) => {
        if (o.isMesh && o.morphTargetInfluences) o.morphTargetInfluences.forEach((w, k, all) => { all[k] = w * params.deform; });
      });
  }
  track();
  slider.value = time;
  $('time').textContent = `t = ${time.toFixed(3)} s` + (params.deform !== 1 ? `, deformation ×${params.deform}` : '');
  requestRender();
}

/** Where the followed body (or the middle of all bodies) is now, glTF axes. */
function followedPoint() {
  if (followed === 'all') return boxOf(bodies).getCenter(new THREE.Vector3());
  followed.updateWorldMatrix(true, false);
  return followed.getWorldPosition(new THREE.Vector3());
}

/** Moves camera and orbit target by as much as the followed body moved since it was last posed. */
function track() {
  if (!followed) return;
  const p = followedPoint();
  if (lastFollowed) {
    const d = p.clone().sub(lastFollowed);
    camera.position.add(d);
    controls.target.add(d);
    controls.update();
  }
  lastFollowed = p;
}

/** The body a follow= value names (null: none), or throws. */
function followTarget(name) {
  if (name === 'none') return null;
  if (name === 'all') return 'all';
  const body = bodies.find((o) => o.name === name || o.name === THREE.PropertyBinding.sanitizeNodeName(name));
  if (!body) throw new Error(`follow=${name}: no body of that name (the bodies: ${bodies.map((o) => o.name).join(', ')}; or all, none)`);
  return body;
}

/**
 * Follows `name` from now on. With `reframe` (the control was used) the
 * camera turns to it: the bodies as they are now, centred on the followed
 * point, seen from the direction the camera looks from now.
 */
function setFollow(name, reframe) {
  followed = followTarget(name);
  lastFollowed = null;
  followSelect.value = name;
  if (followed && reframe) {
    const p = followedPoint();
    frameBox(camera, controls, centredOn(boxOf(bodies), p), camera.position.clone().sub(controls.target));
    controls.update();
  }
  track();
  requestRender();
}

/** The camera, bodies, surfaces and grid now, in the model's world (z up): for tests. */
window.mbgcState = () => {
  const modelFromGltf = (v) => [v.x, -v.z, v.y];
  const where = (o) => modelFromGltf(o.getWorldPosition(new THREE.Vector3()));
  const grid = extras?.children.find((o) => o.type === 'GridHelper');
  return {
    time,
    follow: followSelect.value,
    eye: modelFromGltf(camera.position),
    target: modelFromGltf(controls.target),
    bodies: Object.fromEntries(bodies.map((o) => [o.name, where(o)])),
    surfaces: Object.fromEntries(surfaces.map((o) => [o.name, o.userData.surface])),
    grid: grid ? where(grid)[2] : null,  // the grid's height (none with flat=1)
  };
};

/**
 * A light checkerboard on the ground's surfaces (planes, roads), squares of
 * `cell` metres in their own x-y axes: what shows motion when the camera
 * follows a body over a plain surface, and the scale.
 */
function checker(surfaceNodes, cell) {
  const canvas = document.createElement('canvas');
  canvas.width = canvas.height = 64;
  const g = canvas.getContext('2d');
  g.fillStyle = '#ffffff';
  g.fillRect(0, 0, 64, 64);
  g.fillStyle = '#dcdcdc';
  g.fillRect(0, 0, 32, 32);
  g.fillRect(32, 32, 32, 32);
  const texture = new THREE.CanvasTexture(canvas);
  texture.wrapS = texture.wrapT = THREE.RepeatWrapping;
  texture.colorSpace = THREE.SRGBColorSpace;
  texture.anisotropy = renderer.capabilities.getMaxAnisotropy();
  for (const o of surfaceNodes) {
    if (!o.isMesh || !['plane', 'road'].includes(o.userData.surface)) continue;
    const position = o.geometry.attributes.position, uv = new Float32Array(2 * position.count);
    for (let i = 0; i < position.count; ++i) {
      uv[2 * i] = position.getX(i) / (2 * cell);  // a repeat of the texture: two squares
      uv[2 * i + 1] = position.getY(i) / (2 * cell);
    }
    o.geometry.setAttribute('uv', new THREE.BufferAttribute(uv, 2));
    o.material = o.material.clone();
    o.material.map = texture;
    o.material.needsUpdate = true;
  }
}

/** Bodies in their own colours without light or shade (flat=1), morph targets kept. */
function unlit(root) {
  root.traverse((o) => {
    if (o.isMesh) o.material = new THREE.MeshBasicMaterial({ color: o.material.color, side: THREE.DoubleSide });
  });
}

function show(gltf, name, fromUrl) {
  if (model) scene.remove(model, extras);
  model = gltf.scene;
  if (params.flat) unlit(model);
  scene.add(model);
  const clip = gltf.animations[0];
  mixer = new THREE.AnimationMixer(model);
  action = clip ? mixer.clipAction(clip).play() : null;
  tStart = clip ? Math.min(...clip.tracks.map((track) => track.times[0])) : 0;
  tEnd = clip ? clip.duration : 0;
  slider.min = tStart;
  slider.max = tEnd;
  slider.disabled = playButton.disabled = !clip;

  // The bodies: the root node's children (the file's root turns z up), less the surfaces.
  const top = model.children.length === 1 ? model.children[0] : model;
  surfaces = top.children.filter((o) => o.userData.surface);
  bodies = top.children.filter((o) => !o.userData.surface);
  followed = lastFollowed = null;
  const box = sweptBox(bodies, tStart, tEnd, showAt);
  const paused = fromUrl && params.t !== null;
  showAt(paused ? params.t : tStart);
  const now = boxOf(bodies);
  const everything = box.clone().union(boxOf(surfaces, false));  // and the surfaces (not the model's plain box: its morph targets)
  scale = { centre: everything.getCenter(new THREE.Vector3()), radius: Math.max(everything.getSize(new THREE.Vector3()).length() / 2, 1e-3) };
  extras = params.flat ? new THREE.Group() : helpers(box, everything.min.y);
  scene.add(extras);
  if (!params.flat) checker(surfaces, 10 ** Math.floor(Math.log10(Math.max(largest(now), 1e-6))));

  // Follow: as asked, else the bodies where the run dwarfs them (a vehicle), else nothing.
  const dwarfed = dwarfs(box, now);
  followSelect.replaceChildren(new Option('none', 'none'), new Option('all bodies', 'all'),
    ...bodies.map((o) => new Option(o.name, o.name)));
  followSelect.disabled = bodies.length === 0;
  let follow = dwarfed ? 'all' : 'none';
  if (fromUrl && params.follow !== null) follow = params.follow;
  try {
    followed = followTarget(follow);
  } catch (e) {
    fail(e.message);
    return;
  }
  followSelect.value = followed && followed !== 'all' ? followed.name : follow;
  if (fromUrl && params.camera) {
    camera.position.set(...params.camera.eye);
    controls.target.set(...params.camera.target);
  } else if (followed) {
    frameBox(camera, controls, centredOn(now, followedPoint()));
  } else {
    frameBox(camera, controls, dwarfed ? now : box);
  }
  controls.update();
  lastFollowed = followed ? followedPoint() : null;

  showAt(paused ? params.t : tStart);
  setPlaying(!paused && !!clip);
  message.hidden = true;
  $('name').textContent = name;
  document.title = `mbgc-view: ${name}`;
  window.mbgcReady = false;  // set again once this run's first frame is drawn
  ready = true;
}

// ---- drawing, on demand: after a change, and every frame while playing ----
function requestRender() {
  if (frameRequested) return;
  frameRequested = true;
  requestAnimationFrame(frame);
}
function frame(now) {
  frameRequested = false;
  if (playing) {
    if (lastFrame !== null) {
      const next = time + ((now - lastFrame) / 1000) * params.speed;
      showAt(next > tEnd ? tStart : next);  // loop
    }
    lastFrame = now;
    requestRender();
  }
  if (scale) {  // near and far planes around the scene, wherever the camera went
    const d = camera.position.distanceTo(scale.centre);
    camera.near = Math.max(1e-3 * d, 0.5 * (d - scale.radius));
    camera.far = 2 * (d + scale.radius);
    camera.updateProjectionMatrix();
  }
  renderer.render(scene, camera);
  if (ready) {  // the next frame starts once this one is on screen
    ready = false;
    requestAnimationFrame(() => { window.mbgcReady = true; });
  }
}

function setPlaying(on) {
  playing = on;
  lastFrame = null;
  playButton.textContent = on ? 'Pause' : 'Play';
  requestRender();
}

// ---- opening files: ?file=URL, the file picker, drag and drop ----
const loader = new GLTFLoader();
function openBuffer(buffer, name) {
  loader.parse(buffer, '', (gltf) => show(gltf, name, false), (e) => fail(`${name}: ${e.message ?? e}`));
}
function openFile(file) {
  file.arrayBuffer().then((buffer) => openBuffer(buffer, file.name), (e) => fail(`${file.name}: ${e.message}`));
}
if (params.file) {
  const name = decodeURIComponent(params.file.split('/').pop());
  message.textContent = `Loading ${name}\u2026`;
  loader.load(params.file, (gltf) => show(gltf, name, true), undefined,
    (e) => fail(`${params.file}: ${e.message ?? e}`));
}

$('file').addEventListener('change', (e) => { if (e.target.files[0]) openFile(e.target.files[0]); });
window.addEventListener('dragover', (e) => { e.preventDefault(); document.body.classList.add('dragging'); });
window.addEventListener('dragleave', () => document.body.classList.remove('dragging'));
window.addEventListener('drop', (e) => {
  e.preventDefault();
  document.body.classList.remove('dragging');
  if (e.dataTransfer.files[0]) openFile(e.dataTransfer.files[0]);
});

// ---- play, pause, the time slider, following ----
playButton.addEventListener('click', () => setPlaying(!playing));
followSelect.addEventListener('change', () => setFollow(followSelect.value, true));
slider.addEventListener('input', () => {
  setPlaying(false);
  showAt(Number(slider.value));
});
window.addEventListener('keydown', (e) => {
  if (e.code === 'Space' && model && e.target.tagName !== 'INPUT' && e.target.tagName !== 'SELECT') {
    e.preventDefault();
    setPlaying(!playing);
  }
});

resize();
