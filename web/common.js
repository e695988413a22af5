// What every view of the page shares: the API with the token, three.js set up for vscan's z-up
// scenes with orbit controls, the mesh layout, the instance palette and the picked-item panel.
import * as THREE from './three/build/three.module.js';
import { OrbitControls } from './three/examples/jsm/controls/OrbitControls.js';

export { THREE };
export const BACKGROUND = 0x202020;
const PICK_COLOUR = 0xffff00;
// Colours by instance id (what the page draws and what the tests look for).
export const PALETTE = [0xe6194b, 0x3cb44b, 0x4363d8, 0xf58231, 0x911eb4, 0x42d4f4, 0xf032e6, 0xbfef45, 0xfabed4,
  0x469990];

const token = new URLSearchParams(location.hash.slice(1)).get('token') || '';

export function authHeaders() {
  return token ? { Authorization: `Bearer ${token}` } : {};
}

export async function get(path, as) {
  const response = await fetch(path, { headers: authHeaders() });
  if (!response.ok) throw new Error(`${path}: HTTP ${response.status}: ${(await response.text()).trim()}`);
  return as === 'binary' ? response.arrayBuffer() : response.json();
}

export function showError(message) {
  document.getElementById('error').textContent = message;
  console.error(message);
}

export function setTitle(text) {
  document.getElementById('title').textContent = text;
}

export function instanceColour(instanceId) {
  return new THREE.Color(PALETTE[instanceId % PALETTE.length]);
}

// The API's mesh layout: "VSMH", version, vertex count, triangle count (uint32 LE), then float32
// xyz per vertex and uint32 abc per triangle.
export function parseMesh(buffer) {
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

// A row-major 4x4 from the API (4 rows of 4) as a three.js matrix.
export function matrixFromRows(rows) {
  return new THREE.Matrix4().set(...rows[0], ...rows[1], ...rows[2], ...rows[3]);
}

// Fills table (emptied first) with a heading row and one row per item: a colour swatch (a CSS
// colour) then the item's cells as text.
export function fillSwatchTable(table, headings, items, swatchColour, cells) {
  table.textContent = '';
  const head = table.insertRow();
  for (const name of ['', ...headings]) {
    const th = document.createElement('th');
    th.textContent = name;
    head.appendChild(th);
  }
  for (const item of items) {
    const row = table.insertRow();
    const swatch = document.createElement('span');
    swatch.className = 'swatch';
    swatch.style.background = swatchColour(item);
    row.insertCell().appendChild(swatch);
    for (const value of cells(item)) row.insertCell().textContent = String(value);
  }
  return table;
}

// Fills #picked with name/value rows (null: "nothing picked").
export function showPickedRows(rows) {
  const panel = document.getElementById('picked');
  panel.textContent = '';
  if (!rows) {
    panel.textContent = 'nothing picked';
    return;
  }
  for (const [name, value] of rows) {
    const line = document.createElement('div');
    const key = document.createElement('b');
    key.textContent = `${name}: `;
    line.append(key, String(value));
    panel.appendChild(line);
  }
}

// An order of count points in which every prefix is spread over all of them: the points i with
// i % 16 equal to 0, then 8, 4, 12, 2, ... (bit-reversed), each in stored order. Drawn as an index
// buffer with a draw range, a prefix is a thinned cloud, and picking still reports stored indices.
export function subsampleOrder(count) {
  const order = new Uint32Array(count);
  const offsets = [0, 8, 4, 12, 2, 10, 6, 14, 1, 9, 5, 13, 3, 11, 7, 15];
  let k = 0;
  for (const offset of offsets) {
    for (let i = offset; i < count; i += 16) order[k++] = i;
  }
  return order;
}

// A replay's controls: #play, a range input (sliderId) over frames, and a label after them; both
// disabled when there is nothing to play.
export function playerControls(sliderId, frames) {
  const controls = document.createElement('div');
  const play = document.createElement('button');
  const slider = document.createElement('input');
  const label = document.createElement('span');
  play.id = 'play';
  slider.id = sliderId;
  slider.type = 'range';
  slider.min = '0';
  slider.max = String(Math.max(0, frames - 1));
  slider.disabled = play.disabled = frames === 0;
  controls.append(play, slider, label);
  return { controls, play, slider, label };
}

// A three.js view in #view: a z-up camera that frames what it is given, orbit controls (drag to turn,
// wheel to zoom, right-drag to pan), a headlight that follows the camera, and drawing on demand.
export class Viewer {
  constructor() {
    this.container = document.getElementById('view');
    this.width = this.container.clientWidth;
    this.height = this.container.clientHeight;
    this.world = new THREE.Scene();
    this.world.background = new THREE.Color(BACKGROUND);
    this.camera = new THREE.PerspectiveCamera(45, this.width / this.height, 0.001, 1000);
    this.camera.up.set(0, 0, 1);  // vscan scenes are z-up
    this.world.add(new THREE.AmbientLight(0xffffff, 0.35));
    this.headlight = new THREE.DirectionalLight(0xffffff, 0.65);
    this.world.add(this.headlight, this.headlight.target);
    this.renderer = new THREE.WebGLRenderer({ antialias: false, preserveDrawingBuffer: true });
    this.renderer.setPixelRatio(1);
    this.renderer.setSize(this.width, this.height);
    this.container.appendChild(this.renderer.domElement);
    this.controls = new OrbitControls(this.camera, this.renderer.domElement);
    this.controls.addEventListener('change', () => this.render());
    // While the view turns, the clouds together draw at most this many points (a uniform subsample:
    // see subsampleOrder), and all of them again once it stops.
    this.pointsWhileTurning = 100000;
    this.turning = false;
    this.controls.addEventListener('start', () => { this.turning = true; });
    this.controls.addEventListener('end', () => {
      this.turning = false;
      this.render();
    });
    this.frames = 0;
  }

  // Limits every indexed THREE.Points to its share of pointsWhileTurning while the view turns.
  limitPoints() {
    const clouds = [];
    this.world.traverseVisible((object) => {
      if (object.isPoints && object.geometry.index) clouds.push(object.geometry);
    });
    const total = clouds.reduce((sum, geometry) => sum + geometry.index.count, 0);
    const share = this.turning && total > this.pointsWhileTurning ? this.pointsWhileTurning / total : 1;
    for (const geometry of clouds) {
      geometry.setDrawRange(0, share < 1 ? Math.ceil(geometry.index.count * share) : Infinity);
    }
    return share < 1 ? Math.ceil(total * share) : total;
  }

  // Points the camera at bounds (a THREE.Box3) from the front-right, above, at a distance that fits it.
  frame(bounds) {
    const centre = bounds.isEmpty() ? new THREE.Vector3() : bounds.getCenter(new THREE.Vector3());
    const radius = bounds.isEmpty() ? 1 : Math.max(bounds.getSize(new THREE.Vector3()).length() / 2, 1e-3);
    const distance = radius / Math.sin(this.camera.fov / 2 * Math.PI / 180) * 1.1;
    this.camera.position.copy(centre).add(new THREE.Vector3(1, -1.5, 1).normalize().multiplyScalar(distance));
    this.camera.near = distance / 100;
    this.camera.far = distance * 10;
    this.camera.lookAt(centre);
    this.camera.updateProjectionMatrix();
    this.controls.target.copy(centre);
    this.controls.update();
  }

  render() {
    this.pointsDrawn = this.limitPoints();
    this.headlight.position.copy(this.camera.position);
    this.headlight.target.position.copy(this.controls.target);
    this.world.updateMatrixWorld(true);
    this.camera.updateMatrixWorld(true);
    this.renderer.render(this.world, this.camera);
    this.frames += 1;
  }

  // Calls handler with a Raycaster through the clicked pixel. A drag (the controls turning the view)
  // is not a click.
  onClick(handler) {
    const raycaster = new THREE.Raycaster();
    let down = null;
    this.renderer.domElement.addEventListener('pointerdown', (event) => { down = [event.clientX, event.clientY]; });
    this.renderer.domElement.addEventListener('click', (event) => {
      if (down && Math.hypot(event.clientX - down[0], event.clientY - down[1]) > 4) return;
      const rect = this.renderer.domElement.getBoundingClientRect();
      const pointer = new THREE.Vector2((event.clientX - rect.left) / rect.width * 2 - 1,
        -((event.clientY - rect.top) / rect.height) * 2 + 1);
      raycaster.setFromCamera(pointer, this.camera);
      handler(raycaster);
    });
  }

  // Marks what a click picked (a raycast hit, or null for nothing): a box around a picked mesh, a dot
  // on a picked point; then draws.
  markPicked(hit) {
    if (!this.pickMarks) {
      const dot = new THREE.Points(new THREE.BufferGeometry().setFromPoints([new THREE.Vector3()]),
        new THREE.PointsMaterial({ color: PICK_COLOUR, size: 9, sizeAttenuation: false, depthTest: false }));
      const box = new THREE.Box3Helper(new THREE.Box3(), PICK_COLOUR);
      dot.renderOrder = box.renderOrder = 20;
      this.pickMarks = { dot, box };
      this.world.add(dot, box);
    }
    const { dot, box } = this.pickMarks;
    dot.visible = box.visible = false;
    if (hit && hit.object.isPoints) {
      dot.position.fromBufferAttribute(hit.object.geometry.attributes.position, hit.index)
        .applyMatrix4(hit.object.matrixWorld);
      dot.visible = true;
    } else if (hit && hit.object.isMesh) {
      box.box.setFromObject(hit.object);
      box.visible = true;
    }
    this.render();
  }

  // Where a world point lands in the page, in CSS pixels.
  pixelOf(point) {
    const p = point.clone().project(this.camera);
    return [Math.round((p.x + 1) / 2 * this.width), Math.round((1 - p.y) / 2 * this.height)];
  }
}
