// A mounted robot drawn in a pose (/api/mounts), its sensor's frame on the flange, and a camera's
// viewing frustum.
import { THREE, get, matrixFromRows, parseMesh } from './common.js';

const LINK_COLOUR = 0xb0b0b0;

// Axes of a frame: x red, y green, z (the camera's viewing direction) blue.
export function frameAxes(worldFromFrame, length) {
  const axes = new THREE.AxesHelper(length);
  axes.matrixAutoUpdate = false;
  axes.matrix.copy(worldFromFrame);
  return axes;
}

// The pyramid a pinhole camera sees between near and far (camera: width, height, fx, fy, cx, cy),
// as lines; its frame looks along +z with +y down the image, as vscan's sensor frame does.
export function frustumLines(worldFromSensor, camera, near, far, colour) {
  const corners = (depth) => [[0, 0], [camera.width, 0], [camera.width, camera.height], [0, camera.height]]
    .map(([u, v]) => new THREE.Vector3((u - camera.cx) / camera.fx * depth, (v - camera.cy) / camera.fy * depth, depth));
  const n = corners(near);
  const f = corners(far);
  const points = [];
  for (let i = 0; i < 4; ++i) {
    const j = (i + 1) % 4;
    points.push(n[i], n[j], f[i], f[j], n[i], f[i]);
  }
  const geometry = new THREE.BufferGeometry().setFromPoints(points);
  const lines = new THREE.LineSegments(geometry, new THREE.LineBasicMaterial({ color: colour }));
  lines.matrixAutoUpdate = false;
  lines.matrix.copy(worldFromSensor);
  return lines;
}

// Draws the mount's links at joints (null: the home pose) in viewer.world; returns
// {pose, group, setJoints(joints)} where pose is the API's answer (world_from_sensor among it).
export async function addMountedRobot(viewer, mountId, joints = null) {
  const path = `api/mounts/${encodeURIComponent(mountId)}`;
  const query = (q) => (q ? `?joints=${q.map(String).join(',')}` : '');
  const pose = await get(path + query(joints));
  const group = new THREE.Group();
  const material = new THREE.MeshLambertMaterial({ color: LINK_COLOUR });
  const meshes = [];
  for (let k = 0; k < pose.shapes.length; ++k) {
    const mesh = new THREE.Mesh(parseMesh(await get(`${path}/shapes/${k}`, 'binary')), material);
    mesh.matrixAutoUpdate = false;
    meshes.push(mesh);
    group.add(mesh);
  }
  const sensorAxes = frameAxes(new THREE.Matrix4(), 0.08);
  group.add(sensorAxes);
  const place = (answer) => {
    answer.shapes.forEach((shape, k) => meshes[k].matrix.copy(matrixFromRows(shape.world_from_shape)));
    sensorAxes.matrix.copy(matrixFromRows(answer.world_from_sensor));
  };
  place(pose);
  viewer.world.add(group);
  const robot = {
    pose,
    group,
    meshes,
    async setJoints(q) {
      robot.pose = await get(path + query(q));
      place(robot.pose);
    },
  };
  return robot;
}

// The rotary table as a thin disc of radius about its axis through its centre.
export function tableDisc(table, radius) {
  const disc = new THREE.Mesh(new THREE.CylinderBufferGeometry(radius, radius, radius * 0.04, 48),
    new THREE.MeshLambertMaterial({ color: 0x606070 }));
  // three.js cylinders stand along +y; turn +y onto the table's axis and sink the top to the centre.
  const axis = new THREE.Vector3(...table.axis).normalize();
  disc.quaternion.setFromUnitVectors(new THREE.Vector3(0, 1, 0), axis);
  disc.position.set(...table.centre).addScaledVector(axis, -radius * 0.02);
  return disc;
}
