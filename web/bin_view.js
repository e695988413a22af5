// A bin fill (?bin=JOB_ID): the bin, its parts in their instance colours, the fill played back from
// its bin_replay.bin (play/pause and a time slider; it opens on the final pile), the table of parts,
// a link to the bin's scene, and picking.
import {
  THREE, Viewer, fillSwatchTable, get, instanceColour, matrixFromRows, parseMesh, playerControls, setTitle,
  showPickedRows,
} from './common.js';

const OUTSIDE_COLOUR = 0xb0b0b0;  // parts that left the bin have no instance id
const BIN_COLOUR = 0x707070;
const FLOATS_PER_PART = 7;

// bin_replay.bin (docs/BINS.md): "VSBR", version 1, part count, frame count, float32 sample interval,
// uint32 0; (uint32 type, uint32 instance) per part; per frame float32 time then x y z qx qy qz qw
// per part, NaN while the part is not in the bin's world.
export function parseReplay(buffer) {
  const header = new DataView(buffer, 0, Math.min(24, buffer.byteLength));
  const magic = String.fromCharCode(...new Uint8Array(buffer, 0, Math.min(4, buffer.byteLength)));
  if (buffer.byteLength < 24 || magic !== 'VSBR' || header.getUint32(4, true) !== 1) {
    throw new Error('replay: unknown layout');
  }
  const partCount = header.getUint32(8, true);
  const frameCount = header.getUint32(12, true);
  const frameBytes = 4 + partCount * FLOATS_PER_PART * 4;
  const start = 24 + partCount * 8;
  if (buffer.byteLength !== start + frameCount * frameBytes) throw new Error('replay: truncated');
  const table = new Uint32Array(buffer, 24, partCount * 2);
  const parts = [];
  for (let i = 0; i < partCount; i += 1) parts.push({ type: table[2 * i], instance: table[2 * i + 1] });
  const times = [];
  const poses = [];
  for (let f = 0; f < frameCount; f += 1) {
    const at = start + f * frameBytes;
    times.push(new DataView(buffer, at, 4).getFloat32(0, true));
    poses.push(new Float32Array(buffer, at + 4, partCount * FLOATS_PER_PART));
  }
  return { interval: header.getFloat32(16, true), parts, times, poses };
}

function showTable(bin, content) {
  content.appendChild(fillSwatchTable(document.createElement('table'), ['instance', 'type', 'object'], bin.parts,
    (part) => `#${instanceColour(part.instance_id ?? 0).getHexString()}`,
    (part) => [part.instance_id === null ? '' : part.instance_id, part.name, part.object_id]));
}

function showPicked(part) {
  window.vscanPicked = part && {
    instance_id: part.instance_id, type: part.type, name: part.name, label: part.label, object_id: part.object_id,
  };
  showPickedRows(part && [['instance', part.instance_id === null ? 'none (out of the bin)' : String(part.instance_id)],
    ['type', `${part.name} (${part.type})`], ['label', part.label], ['object', part.object_id || 'none']]);
}

// The bin as drawn: a box's floor and walls from its sizes (as the fill laid them out), or its mesh.
export async function addBin(viewer, bin) {
  const material = new THREE.MeshLambertMaterial({ color: BIN_COLOUR });
  const group = new THREE.Group();
  group.matrixAutoUpdate = false;
  group.matrix.copy(matrixFromRows(bin.world_from_bin));
  if (bin.kind === 'box') {
    const [sx, sy, sz] = bin.inner_size;
    const w = bin.wall_thickness;
    for (const [centre, size] of [
      [[0, 0, -w / 2], [sx + 2 * w, sy + 2 * w, w]],
      [[(sx + w) / 2, 0, sz / 2], [w, sy + 2 * w, sz]], [[-(sx + w) / 2, 0, sz / 2], [w, sy + 2 * w, sz]],
      [[0, (sy + w) / 2, sz / 2], [sx, w, sz]], [[0, -(sy + w) / 2, sz / 2], [sx, w, sz]]]) {
      const box = new THREE.Mesh(new THREE.BoxBufferGeometry(...size), material);
      box.position.set(...centre);
      group.add(box);
    }
  } else {
    const mesh = new THREE.Mesh(parseMesh(await get(`api/meshes/${encodeURIComponent(bin.mesh_id)}`, 'binary')),
      material);
    mesh.scale.setScalar(bin.scale);
    group.add(mesh);
  }
  viewer.world.add(group);
  return group;
}

// Looks at bounds from above, a little from the front, so that the pile shows over the front wall.
// On a wide page the bin is drawn right of the panel (the view's centre moved by a view offset).
export function frameFromAbove(viewer, bounds) {
  const { camera, width, height } = viewer;
  const panel = document.getElementById('panel').getBoundingClientRect().right + 8;
  const left = width > 1.4 * height ? Math.min(panel, 0.55 * width) : 0;
  const halfWidth = (width - left) / 2;
  camera.setViewOffset(width, height, width / 2 - (left + halfWidth), 0, width, height);
  const centre = bounds.getCenter(new THREE.Vector3());
  const radius = Math.max(bounds.getSize(new THREE.Vector3()).length() / 2, 1e-3);
  const tanHalf = Math.tan(camera.fov / 2 * Math.PI / 180) * Math.min(1, halfWidth / (height / 2));
  const distance = radius / Math.sin(Math.atan(tanHalf)) * 1.05;
  camera.position.copy(centre).add(new THREE.Vector3(0.25, -0.45, 1).normalize().multiplyScalar(distance));
  camera.near = distance / 100;
  camera.far = distance * 10;
  camera.lookAt(centre);
  camera.updateProjectionMatrix();
  viewer.controls.target.copy(centre);
  viewer.controls.update();
}

function key(type, instance) { return `${type}/${instance}`; }

export async function showBin(id) {
  const bin = await get(`api/bins/${encodeURIComponent(id)}`);
  setTitle(`vscan: bin fill ${bin.name || bin.job_id} (${bin.job_id}, ${bin.state})`);
  const content = document.getElementById('content');
  const summary = document.createElement('div');
  summary.textContent = bin.message;
  content.appendChild(summary);
  if (!bin.report) {
    const note = document.createElement('div');
    note.textContent = ['QUEUED', 'RUNNING'].includes(bin.state)
      ? `${bin.steps_done} of ${bin.steps_total} parts dropped; the pile is shown once the fill ends (reload)`
      : 'the fill ended before its physics ran: there is no pile';
    content.appendChild(note);
    window.vscanView = { job_id: bin.job_id, state: bin.state, parts: [], frames: 0, frame: 0 };
    return;
  }
  if (bin.scene_id) {
    const link = document.createElement('a');
    link.id = 'scene-link';
    link.href = `?scene=${encodeURIComponent(bin.scene_id)}${location.hash}`;
    link.textContent = bin.applied ? `the bin's scene (${bin.scene_id}, revision ${bin.scene_revision})`
      : `the scene (${bin.scene_id}; this fill did not change it)`;
    content.appendChild(link);
  }

  const replay = bin.replay ? parseReplay(await get(`api/bins/${encodeURIComponent(id)}/replay`, 'binary')) : null;
  const viewer = new Viewer();
  const binGroup = await addBin(viewer, bin.bin);
  const types = new Map(bin.types.map((t) => [t.type, t]));
  const geometries = new Map();
  for (const meshId of new Set(bin.types.map((t) => t.mesh_id))) {
    geometries.set(meshId, parseMesh(await get(`api/meshes/${encodeURIComponent(meshId)}`, 'binary')));
  }
  // The parts drawn: every part the replay has (those that left the bin too), else bin.json's.
  const finals = new Map(bin.parts.map((p) => [key(p.type, p.instance), p]));
  const drawn = (replay ? replay.parts : bin.parts).map(({ type, instance }) => {
    const placed = finals.get(key(type, instance));
    const kind = types.get(type);
    const part = placed || {
      type, instance, name: kind.name, label: `${kind.name}#${instance + 1}`, object_id: '', instance_id: null,
      mesh_id: kind.mesh_id, scale: kind.scale,
    };
    const colour = part.instance_id === null ? new THREE.Color(OUTSIDE_COLOUR) : instanceColour(part.instance_id);
    const mesh = new THREE.Mesh(geometries.get(part.mesh_id), new THREE.MeshLambertMaterial({ color: colour }));
    mesh.matrixAutoUpdate = false;
    viewer.world.add(mesh);
    return { part, mesh, colour };
  });
  const scaleOf = (part) => new THREE.Vector3(part.scale, part.scale, part.scale);

  // Frame f of the replay (the final pile of bin.json without one).
  let frame = replay ? replay.times.length - 1 : 0;
  const position = new THREE.Vector3();
  const rotation = new THREE.Quaternion();
  function pose(f) {
    drawn.forEach(({ part, mesh }, i) => {
      if (!replay) {
        mesh.matrix.copy(matrixFromRows(part.world_from_part)).multiply(new THREE.Matrix4().makeScale(part.scale,
          part.scale, part.scale));
        return;
      }
      const p = replay.poses[f].subarray(i * FLOATS_PER_PART, (i + 1) * FLOATS_PER_PART);
      mesh.visible = !Number.isNaN(p[0]);
      if (!mesh.visible) return;
      position.set(p[0], p[1], p[2]);
      rotation.set(p[3], p[4], p[5], p[6]);
      mesh.matrix.compose(position, rotation, scaleOf(part));
    });
    viewer.world.updateMatrixWorld(true);
  }

  const { controls, play, slider, label: clock } = playerControls('frame', replay ? replay.times.length : 0);
  content.appendChild(controls);
  if (!replay) clock.textContent = ' no replay recorded for this fill';

  let playing = false;
  let clockAt = 0;  // performance.now() of the last tick
  let playTime = 0;  // simulated seconds shown, advanced by the wall clock while playing
  function show(f) {
    frame = Math.max(0, Math.min(f, replay ? replay.times.length - 1 : 0));
    pose(frame);
    slider.value = String(frame);
    if (replay) clock.textContent = ` ${replay.times[frame].toFixed(2)} s of ${replay.times.at(-1).toFixed(2)} s`;
    play.textContent = playing ? 'pause' : 'play';
    if (window.vscanView) window.vscanView.frame = frame;
    viewer.render();
  }
  // Plays in simulated time (one simulated second a second), from the start when at the end.
  function tick(now) {
    if (!playing) return;
    playTime += Math.max(0, now - clockAt) / 1000;
    clockAt = now;
    let f = frame;
    while (f + 1 < replay.times.length && replay.times[f + 1] <= playTime) f += 1;
    if (f + 1 >= replay.times.length) playing = false;
    show(f);
    if (playing) requestAnimationFrame(tick);
  }
  play.addEventListener('click', () => {
    playing = !playing;
    if (playing) {
      if (frame >= replay.times.length - 1) frame = 0;
      playTime = replay.times[frame];
      clockAt = performance.now();
      requestAnimationFrame(tick);
    }
    show(frame);
  });
  slider.addEventListener('input', () => {
    playing = false;
    show(Number(slider.value));
  });

  showTable(bin, content);
  pose(frame);
  const bounds = new THREE.Box3().setFromObject(binGroup);
  for (const { mesh } of drawn) if (mesh.visible) bounds.expandByObject(mesh);
  frameFromAbove(viewer, bounds);

  const meshes = drawn.map(({ mesh }) => mesh);
  window.vscanPickCount = 0;
  viewer.onClick((raycaster) => {
    const [hit] = raycaster.intersectObjects(meshes.filter((m) => m.visible));
    showPicked(hit ? drawn[meshes.indexOf(hit.object)].part : null);
    viewer.markPicked(hit || null);
    window.vscanPickCount += 1;
  });

  // Each part with where its final bounds centre lands in the page (CSS pixels) and its colour; the
  // frame shown and how many there are; vscanSeek(f) shows frame f (paused) and returns the parts' centres.
  const centreOf = (mesh) => (mesh.visible ? new THREE.Box3().setFromObject(mesh).getCenter(new THREE.Vector3())
    : null);
  window.vscanViewer = viewer;
  window.vscanView = {
    job_id: bin.job_id,
    scene_id: bin.scene_id,
    frames: replay ? replay.times.length : 0,
    frame,
    parts: drawn.map(({ part, mesh, colour }) => {
      const centre = centreOf(mesh);
      return {
        type: part.type, instance: part.instance, instance_id: part.instance_id, object_id: part.object_id,
        colour: [colour.r, colour.g, colour.b].map((v) => Math.round(v * 255)),
        centre: centre && centre.toArray(),
        pixel: centre && viewer.pixelOf(centre),
      };
    }),
  };
  window.vscanSeek = (f) => {
    playing = false;
    show(f);
    return { frame, time: replay ? replay.times[frame] : null,
      centres: drawn.map(({ mesh }) => { const c = centreOf(mesh); return c && c.toArray(); }) };
  };
  show(frame);
}
