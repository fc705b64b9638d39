// Where the default camera goes, and the helpers (grid, axes) sized to the
// scene: both from the box the bodies sweep over the whole run (surfaces,
// which the runtime sizes to cover that sweep, are left out), or from the
// bodies at the time shown where the sweep dwarfs them.
import * as THREE from 'three';
import { gltfFromModel } from './params.js';

/**
 * The box (glTF axes) the objects cover as they are posed now: precise, from
 * the vertices as deformed by the current morph weights (three.js's plain box
 * of a morphed mesh holds every morph target at full weight: metres for a
 * flexible beam of centimetres); `precise = false` for what has no morph
 * targets (surfaces).
 */
export function boxOf(objects, precise = true) {
  const box = new THREE.Box3();
  for (const o of objects) {
    o.updateWorldMatrix(true, true);
    box.union(new THREE.Box3().setFromObject(o, precise));
  }
  return box;
}

/** The box (glTF axes) the objects cover over the run: `showAt(t)` poses them at t. */
export function sweptBox(objects, tStart, tEnd, showAt) {
  const box = new THREE.Box3();
  const samples = tEnd > tStart ? 100 : 0;
  for (let k = 0; k <= samples; ++k) {
    showAt(tStart + ((tEnd - tStart) * k) / Math.max(samples, 1));
    box.union(boxOf(objects));
  }
  if (box.isEmpty()) box.setFromCenterAndSize(new THREE.Vector3(), new THREE.Vector3(1, 1, 1));
  return box;
}

/** The largest edge of a box. */
export function largest(box) {
  const size = box.getSize(new THREE.Vector3());
  return Math.max(size.x, size.y, size.z);
}

/**
 * Whether the motion dwarfs the bodies: the box they sweep over the run is
 * more than ten times the size of the box they fill at one time (a vehicle
 * driving 160 m; not a pendulum, a bouncing ball or a snap-fit).
 */
export function dwarfs(swept, now) {
  return largest(swept) > 10 * Math.max(largest(now), 1e-9);
}

/** The box grown to be symmetric about `point` (so that, framed, the point is in the middle). */
export function centredOn(box, point) {
  const out = box.clone();
  out.expandByPoint(point.clone().multiplyScalar(2).sub(box.min));
  out.expandByPoint(point.clone().multiplyScalar(2).sub(box.max));
  return out;
}

/**
 * The direction (model axes, z up) from the scene's centre to the default
 * camera: from the front right and above; for a scene flat in one axis (a
 * planar mechanism) mostly along that axis, so that the motion is seen face on.
 */
function viewDirection([sx, sy, sz]) {
  const largest = Math.max(sx, sy, sz);
  if (sz <= 0.1 * largest) return [0.2, -0.4, 1];  // in the x-y plane: from above, y up the screen
  if (sy <= 0.1 * largest) return [0.3, -1, 0.3];  // in the x-z plane: from the front
  if (sx <= 0.1 * largest) return [1, 0.3, 0.3];   // in the y-z plane: from the side
  return [1, -1.6, 0.9];
}

/**
 * Puts the camera where the whole box is in view, as close as it can: along
 * the view direction (`direction`, glTF axes, from the box's centre to the
 * camera; default: by the box's shape), each corner of the box needs the
 * camera at least so far back that the corner is inside the field of view,
 * across and up.
 */
export function frameBox(camera, controls, box, direction = null) {
  const centre = box.getCenter(new THREE.Vector3());
  const size = box.getSize(new THREE.Vector3());  // glTF axes: the model's extents are x, z, y
  const back = (direction ? direction.clone() : new THREE.Vector3(...gltfFromModel(viewDirection([size.x, size.z, size.y])))).normalize();
  const right = new THREE.Vector3().crossVectors(camera.up, back);
  if (right.lengthSq() < 1e-12) right.set(1, 0, 0);  // looking straight down the up axis
  right.normalize();
  const up = new THREE.Vector3().crossVectors(back, right);
  const tanUp = Math.tan(THREE.MathUtils.degToRad(camera.fov) / 2), tanAcross = tanUp * camera.aspect;
  let distance = 1e-3;
  for (const corner of [box.min, box.max].flatMap((a) => [box.min, box.max].flatMap((b) => [box.min, box.max].map((c) =>
    new THREE.Vector3(a.x, b.y, c.z).sub(centre))))) {
    const z = corner.dot(back);
    distance = Math.max(distance, z + Math.abs(corner.dot(right)) / tanAcross, z + Math.abs(corner.dot(up)) / tanUp);
  }
  camera.position.copy(centre).addScaledVector(back, 1.1 * distance);
  controls.target.copy(centre);
}

/**
 * A grid under the scene in the model's x-y plane (below `floor` too, the
 * lowest point of the drawn surfaces, so that a ground surface hides it), and
 * the model's axes at its origin (x red, y green, z blue).
 */
export function helpers(box, floor = Infinity) {
  const group = new THREE.Group();
  const size = box.getSize(new THREE.Vector3());
  const extent = Math.max(size.x, size.z, 1e-3);  // across the model's x-y plane
  const step = 10 ** Math.round(Math.log10(extent / 5));
  const divisions = 2 * Math.ceil((0.6 * extent) / step);
  const grid = new THREE.GridHelper(divisions * step, divisions, 0x999999, 0xcccccc);
  const centre = box.getCenter(new THREE.Vector3());
  grid.position.set(Math.round(centre.x / step) * step, Math.min(box.min.y, floor) - 0.02 * extent, Math.round(centre.z / step) * step);
  group.add(grid);
  const axes = new THREE.AxesHelper(0.15 * Math.max(size.x, size.y, size.z, 1e-3));
  axes.rotation.x = -Math.PI / 2;  // as the file's root node: the model's z up
  group.add(axes);
  return group;
}
