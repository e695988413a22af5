// The vscan web view: reads one scene (?scene=ID) over the read-only API with the token from the
// URL fragment (#token=...) and draws its objects with three.js. Without ?scene it lists the scenes.
// A click on the drawing reports the object under it (three.js's Raycaster) in #picked.
import * as THREE from './three.module.js';

const BACKGROUND = 0x202020;
// Colours by instance id (what the page draws and what the tests look for).
const PALETTE = [0xe6194b, 0x3cb44b, 0x4363d8, 0xf58231, 0x911eb4, 0x42d4f4, 0xf032e6, 0xbfef45, 0xfabed4, 0x469990];

const token = new URLSearchParams(location.hash.slice(1)).get('token') || '';
const sceneId = new URLSearchParams(location.search).get('scene');

function showError(message) {
  document.getElementById('error').textContent = message;
  console.error(message);
}

async function get(path, as) {
  const headers = token ? { Authorization: `Bearer ${token}` } : {};
  const response = await fetch(path, { headers });
  if (!response.ok) throw new Error(`${path}: HTTP ${response.status}: ${(await response.text()).trim()}`);
  return as === 'binary' ? response.arrayBuffer() : response.json();
}

// The API's mesh layout: "VSMH", version, vertex count, triangle count (uint32 LE), then float32
// xyz per vertex and uint32 abc per triangle.
function parseMesh(buffer) {
  const header = new DataView(buffer, 0, 16);
  const magic = String.fromCharCode(...new Uint8Array(buffer, 0, 4));
  if (magic !== 'VSMH' || header.getUint32(4, true) !== 1) throw new Error('mesh: unknown layout');
  const vertices = header.getUint32(8, true);
  const triangles = header.getUint32(12, true);
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute('position', new THREE.BufferAttribute(new Float32Array(buffer, 16, vertices * 3), 3));
  geometry.setIndex(new THREE.BufferAttribute(new Uint32Array(buffer, 16 + vertices * 12, triangles * 3), 1));
  geometry.computeVertexNormals();
  return geometry;
}

function colourOf(object) {
  return new THREE.Color(PALETTE[object.instance_id % PALETTE.length]);
}

function cell(row, text) {
  const td = document.createElement('td');
  td.textContent = text;
  row.appendChild(td);
  return td;
}

function showTable(scene) {
  const table = document.createElement('table');
  const head = table.insertRow();
  for (const name of ['', 'object', 'label', 'mesh', 'instance', 'material', 'albedo']) {
    const th = document.createElement('th');
    th.textContent = name;
    head.appendChild(th);
  }
  for (const object of scene.objects) {
    const row = table.insertRow();
    const swatch = document.createElement('span');
    swatch.className = 'swatch';
    swatch.style.background = `#${colourOf(object).getHexString()}`;
    cell(row, '').appendChild(swatch);
    cell(row, object.object_id);
    cell(row, object.label);
    cell(row, object.mesh_id);
    cell(row, String(object.instance_id));
    cell(row, object.material ? object.material.preset : '');
    cell(row, object.material ? String(object.material.albedo) : '');
  }
  document.getElementById('content').appendChild(table);
}

function describeMaterial(material) {
  if (!material) return '';
  const values = `albedo ${material.albedo}, metallic ${material.metallic}, roughness ${material.roughness}, ` +
    `specular ${material.specular_reflectance}`;
  return material.preset ? `${material.preset} (${values})` : values;
}

// Fills #picked with the clicked object (null: the click hit nothing) and keeps it in window.vscanPicked.
function showPicked(object) {
  const panel = document.getElementById('picked');
  panel.textContent = '';
  window.vscanPicked = object && {
    object_id: object.object_id, label: object.label, instance_id: object.instance_id, material: object.material,
  };
  if (!object) {
    panel.textContent = 'nothing picked';
    return;
  }
  const rows = [['object', object.object_id], ['label', object.label], ['instance', String(object.instance_id)],
    ['material', describeMaterial(object.material)]];
  for (const [name, value] of rows) {
    const line = document.createElement('div');
    const key = document.createElement('b');
    key.textContent = `${name}: `;
    line.append(key, value);
    panel.appendChild(line);
  }
}

async function listScenes() {
  const { scenes } = await get('api/scenes');
  const list = document.createElement('ul');
  for (const scene of scenes) {
    const item = document.createElement('li');
    const link = document.createElement('a');
    link.href = `?scene=${encodeURIComponent(scene.scene_id)}${location.hash}`;
    link.textContent = `${scene.name || scene.scene_id} (${scene.scene_id}, ${scene.object_count} objects)`;
    item.appendChild(link);
    list.appendChild(item);
  }
  document.getElementById('title').textContent = `vscan: ${scenes.length} scenes`;
  document.getElementById('content').appendChild(list);
}

async function showScene(id) {
  const scene = await get(`api/scenes/${encodeURIComponent(id)}`);
  document.getElementById('title').textContent = `vscan: ${scene.name || scene.scene_id} (${scene.scene_id}, revision ${scene.revision})`;
  showTable(scene);

  const geometries = new Map();
  for (const meshId of new Set(scene.objects.map((o) => o.mesh_id))) {
    geometries.set(meshId, parseMesh(await get(`api/meshes/${encodeURIComponent(meshId)}`, 'binary')));
  }

  const world = new THREE.Scene();
  world.background = new THREE.Color(BACKGROUND);
  const placed = [];
  for (const object of scene.objects) {
    const mesh = new THREE.Mesh(geometries.get(object.mesh_id), new THREE.MeshLambertMaterial({ color: colourOf(object) }));
    const m = object.world_from_object;
    const pose = new THREE.Matrix4().set(...m[0], ...m[1], ...m[2], ...m[3]);
    mesh.matrixAutoUpdate = false;
    mesh.matrix.copy(pose.multiply(new THREE.Matrix4().makeScale(object.scale, object.scale, object.scale)));
    world.add(mesh);
    placed.push({ object, mesh });
  }
  world.updateMatrixWorld(true);

  const container = document.getElementById('view');
  const width = container.clientWidth;
  const height = container.clientHeight;
  const camera = new THREE.PerspectiveCamera(45, width / height, 0.001, 1000);
  camera.up.set(0, 0, 1);  // vscan scenes are z-up
  const bounds = new THREE.Box3();
  for (const { mesh } of placed) bounds.expandByObject(mesh);
  const centre = bounds.isEmpty() ? new THREE.Vector3() : bounds.getCenter(new THREE.Vector3());
  const radius = bounds.isEmpty() ? 1 : Math.max(bounds.getSize(new THREE.Vector3()).length() / 2, 1e-3);
  const distance = radius / Math.sin(camera.fov / 2 * Math.PI / 180) * 1.1;
  camera.position.copy(centre).add(new THREE.Vector3(1, -1.5, 1).normalize().multiplyScalar(distance));
  camera.near = distance / 100;
  camera.far = distance * 10;
  camera.lookAt(centre);
  camera.updateProjectionMatrix();
  camera.updateMatrixWorld(true);

  // A light from the camera plus ambient: surfaces facing the viewer show their full colour.
  world.add(new THREE.AmbientLight(0xffffff, 0.35));
  const headlight = new THREE.DirectionalLight(0xffffff, 0.65);
  headlight.position.copy(camera.position);
  headlight.target.position.copy(centre);
  world.add(headlight, headlight.target);

  const renderer = new THREE.WebGLRenderer({ antialias: false, preserveDrawingBuffer: true });
  renderer.setPixelRatio(1);
  renderer.setSize(width, height);
  container.appendChild(renderer.domElement);
  renderer.render(world, camera);

  // A click reports the nearest object under the pointer, or that none is there.
  const raycaster = new THREE.Raycaster();
  const meshes = placed.map(({ mesh }) => mesh);
  window.vscanPickCount = 0;
  renderer.domElement.addEventListener('click', (event) => {
    const rect = renderer.domElement.getBoundingClientRect();
    const pointer = new THREE.Vector2((event.clientX - rect.left) / rect.width * 2 - 1,
      -((event.clientY - rect.top) / rect.height) * 2 + 1);
    raycaster.setFromCamera(pointer, camera);
    const [hit] = raycaster.intersectObjects(meshes);
    showPicked(hit ? placed[meshes.indexOf(hit.object)].object : null);
    window.vscanPickCount += 1;
  });

  // Where each object's bounds centre lands in the page (CSS pixels), for checks of what is drawn.
  window.vscanView = {
    scene_id: scene.scene_id,
    objects: placed.map(({ object, mesh }) => {
      const c = new THREE.Box3().setFromObject(mesh).getCenter(new THREE.Vector3()).project(camera);
      const colour = colourOf(object);
      return {
        object_id: object.object_id,
        colour: [colour.r, colour.g, colour.b].map((v) => Math.round(v * 255)),
        pixel: [Math.round((c.x + 1) / 2 * width), Math.round((1 - c.y) / 2 * height)],
      };
    }),
  };
}

async function main() {
  try {
    if (sceneId) await showScene(sceneId); else await listScenes();
  } catch (error) {
    showError(error.message);
    window.vscanError = error.message;
  } finally {
    window.vscanReady = true;
  }
}

main();
