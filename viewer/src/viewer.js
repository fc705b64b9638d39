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
// For tests and stills (viewer/headless.mjs): URL parameters (params.js) fix
// the time and the camera, and once the frame at that time is on screen the
// page sets window.mbgcReady = true (or window.mbgcError to a message).
import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';
import { parseParameters } from './params.js';
import { sweptBox, frameBox, helpers } from './framing.js';

const $ = (id) => document.getElementById(id);
const view = $('view'), message = $('message'), playButton = $('play'), slider = $('slider');

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
  slider.value = time;
  $('time').textContent = `t = ${time.toFixed(3)} s` + (params.deform !== 1 ? `, deformation ×${params.deform}` : '');
  requestRender();
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

  const box = sweptBox(model, tStart, tEnd, showAt);
  scale = { centre: box.getCenter(new THREE.Vector3()), radius: Math.max(box.getSize(new THREE.Vector3()).length() / 2, 1e-3) };
  extras = params.flat ? new THREE.Group() : helpers(box);
  scene.add(extras);
  if (fromUrl && params.camera) {
    camera.position.set(...params.camera.eye);
    controls.target.set(...params.camera.target);
  } else {
    frameBox(camera, controls, box);
  }
  controls.update();

  const paused = fromUrl && params.t !== null;
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

// ---- play, pause, the time slider ----
playButton.addEventListener('click', () => setPlaying(!playing));
slider.addEventListener('input', () => {
  setPlaying(false);
  showAt(Number(slider.value));
});
window.addEventListener('keydown', (e) => {
  if (e.code === 'Space' && model && e.target.tagName !== 'INPUT') {
    e.preventDefault();
    setPlaying(!playing);
  }
});

resize();
