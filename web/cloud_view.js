// A stored cloud (?cloud=ID): its points, coloured by instance id when it has them, else by
// intensity, and picking. Also the API's cloud layout and point drawing the job view uses.
import { THREE, Viewer, get, instanceColour, matrixFromRows, setTitle, showPickedRows, subsampleOrder } from './common.js';

// PointFields bits (what the layout's header says the cloud carries).
export const FIELD = {
  position: 1, normal: 2, range: 4, intensity: 8, instance: 16, pixel: 32, clean: 64, incidence: 128, status: 256,
  estimatedNormal: 512,
};
// vscan.v1.PointStatus by value.
const STATUS = ['unspecified', 'measured', 'outlier', 'flying pixel', 'rejected: out of range', 'rejected: shadowed',
  'rejected: grazing', 'rejected: dim', 'rejected: unlit', 'rejected: dark', 'rejected: saturated',
  'rejected: interreflection'];

// The API's cloud layout (docs/WEB.md): "VSCL", version, fields, count, total (uint64), image width
// and height, then float32 xyz and one array per field present, in the order of its bit.
export function parseCloud(buffer) {
  const view = new DataView(buffer);
  const magic = String.fromCharCode(...new Uint8Array(buffer, 0, 4));
  if (magic !== 'VSCL' || view.getUint32(4, true) !== 1) throw new Error('cloud: unknown layout');
  const fields = view.getUint32(8, true);
  const count = view.getUint32(12, true);
  const cloud = {
    fields, count, total: view.getUint32(16, true) + view.getUint32(20, true) * 2 ** 32,
    width: view.getUint32(24, true), height: view.getUint32(28, true),
  };
  let offset = 32;
  const take = (Type, length) => {
    const array = new Type(buffer, offset, length);
    offset += array.byteLength;
    return array;
  };
  cloud.positions = take(Float32Array, count * 3);
  if (fields & FIELD.normal) cloud.normals = take(Float32Array, count * 3);
  if (fields & FIELD.range) cloud.ranges = take(Float32Array, count);
  if (fields & FIELD.intensity) cloud.intensities = take(Float32Array, count);
  if (fields & FIELD.instance) cloud.instances = take(Uint32Array, count);
  if (fields & FIELD.pixel) cloud.pixels = take(Uint32Array, count);
  if (fields & FIELD.clean) cloud.cleanPositions = take(Float32Array, count * 3);
  if (fields & FIELD.incidence) cloud.incidences = take(Float32Array, count);
  if (fields & FIELD.status) {
    cloud.statuses = take(Uint8Array, count);
    offset += (4 - (count % 4)) % 4;
  }
  if (fields & FIELD.estimatedNormal) cloud.estimatedNormals = take(Float32Array, count * 3);
  if (offset !== buffer.byteLength) throw new Error(`cloud: ${buffer.byteLength} bytes, the header says ${offset}`);
  return cloud;
}

// The point's colour: its instance's, else its intensity as grey (scaled to the cloud's brightest),
// else light grey.
function colours(cloud) {
  const out = new Float32Array(cloud.count * 3);
  let brightest = 0;
  if (!cloud.instances && cloud.intensities) {
    for (const v of cloud.intensities) if (Number.isFinite(v) && v > brightest) brightest = v;
  }
  const colour = new THREE.Color();
  for (let i = 0; i < cloud.count; i += 1) {
    if (cloud.instances) {
      colour.copy(instanceColour(cloud.instances[i]));
    } else if (cloud.intensities && brightest > 0) {
      const g = 0.15 + 0.85 * Math.min(Math.max(cloud.intensities[i] / brightest, 0), 1);
      colour.setRGB(g, g, g);
    } else {
      colour.setRGB(0.8, 0.8, 0.8);
    }
    out[i * 3] = colour.r;
    out[i * 3 + 1] = colour.g;
    out[i * 3 + 2] = colour.b;
  }
  return out;
}

// The cloud as THREE.Points, placed by worldFromCloud (a THREE.Matrix4, or null: as it is), with
// the cloud kept in userData for picking. A fixed colour replaces the per-point ones when given.
export function cloudPoints(cloud, worldFromCloud, size = 2, colour = null) {
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute('position', new THREE.BufferAttribute(cloud.positions, 3));
  geometry.setIndex(new THREE.BufferAttribute(subsampleOrder(cloud.count), 1));
  const material = colour === null
    ? new THREE.PointsMaterial({ size, sizeAttenuation: false, vertexColors: true })
    : new THREE.PointsMaterial({ size, sizeAttenuation: false, color: colour });
  if (colour === null) geometry.setAttribute('color', new THREE.BufferAttribute(colours(cloud), 3));
  const points = new THREE.Points(geometry, material);
  if (worldFromCloud) {
    points.matrixAutoUpdate = false;
    points.matrix.copy(worldFromCloud);
  }
  points.userData.cloud = cloud;
  return points;
}

// Where a stored cloud's points lie in the world: sensor-frame clouds through the pose they carry.
export function worldFromRecord(record) {
  return record.frame === 'sensor' && record.world_from_sensor ? matrixFromRows(record.world_from_sensor) : null;
}

const round = (v, digits = 4) => Number(v.toFixed(digits));

// What a picked point carries: {index, position (world), range, intensity, status, instance_id,
// pixel: [u, v] or pixel_index, incidence_deg}, only the fields the cloud has.
export function pointFields(points, index) {
  const cloud = points.userData.cloud;
  const p = new THREE.Vector3().fromArray(cloud.positions, index * 3).applyMatrix4(points.matrixWorld);
  const out = { index, position: [round(p.x), round(p.y), round(p.z)] };
  if (cloud.ranges) out.range = round(cloud.ranges[index]);
  if (cloud.intensities) out.intensity = round(cloud.intensities[index]);
  if (cloud.statuses) out.status = STATUS[cloud.statuses[index]] || String(cloud.statuses[index]);
  if (cloud.instances) out.instance_id = cloud.instances[index];
  if (cloud.pixels) {
    if (cloud.width > 0) out.pixel = [cloud.pixels[index] % cloud.width, Math.floor(cloud.pixels[index] / cloud.width)];
    else out.pixel_index = cloud.pixels[index];
  }
  if (cloud.incidences) out.incidence_deg = round(cloud.incidences[index] * 180 / Math.PI, 2);
  return out;
}

// Fills #picked with a point's fields.
export function showPickedPoint(fields, label) {
  if (!fields) {
    showPickedRows(null);
    return;
  }
  const rows = [];
  if (label) rows.push(['cloud', label]);
  rows.push(['point', fields.index], ['position', fields.position.join(', ')]);
  if ('range' in fields) rows.push(['range', `${fields.range} m`]);
  if ('intensity' in fields) rows.push(['intensity', fields.intensity]);
  if ('status' in fields) rows.push(['status', fields.status]);
  if ('instance_id' in fields) rows.push(['instance', fields.instance_id]);
  if ('pixel' in fields) rows.push(['pixel', `u ${fields.pixel[0]}, v ${fields.pixel[1]}`]);
  if ('pixel_index' in fields) rows.push(['pixel index', fields.pixel_index]);
  if ('incidence_deg' in fields) rows.push(['incidence', `${fields.incidence_deg} deg`]);
  showPickedRows(rows);
}

// A pick radius in world units for the clouds in bounds: about a pixel and a half at the framed distance.
export function pickThreshold(viewer, bounds) {
  const size = bounds.isEmpty() ? 1 : bounds.getSize(new THREE.Vector3()).length();
  return Math.max(size * 1.5 / Math.min(viewer.width, viewer.height), 1e-5);
}

// Some points spread over the cloud and where the page draws them, for the tests to click.
function samplePixels(viewer, points, samples) {
  const cloud = points.userData.cloud;
  const out = [];
  const step = Math.max(1, Math.floor(cloud.count / samples));
  for (let i = 0; i < cloud.count && out.length < samples; i += step) {
    const p = new THREE.Vector3().fromArray(cloud.positions, i * 3).applyMatrix4(points.matrixWorld);
    out.push({ index: i, pixel: viewer.pixelOf(p) });
  }
  return out;
}

export async function showCloud(id, query) {
  const maxPoints = query.get('max_points');
  const [record, buffer] = await Promise.all([
    get(`api/clouds/${encodeURIComponent(id)}/record`),
    get(`api/clouds/${encodeURIComponent(id)}${maxPoints ? `?max_points=${encodeURIComponent(maxPoints)}` : ''}`,
      'binary'),
  ]);
  const cloud = parseCloud(buffer);
  setTitle(`vscan: cloud ${record.name} (${record.cloud_id}): ${cloud.count} of ${cloud.total} points` +
    ` [${record.fields.join(', ')}]`);
  const viewer = new Viewer();
  const points = cloudPoints(cloud, worldFromRecord(record));
  viewer.world.add(points);
  viewer.world.updateMatrixWorld(true);
  points.geometry.computeBoundingBox();
  const bounds = points.geometry.boundingBox.clone().applyMatrix4(points.matrixWorld);
  viewer.frame(bounds);
  viewer.render();
  // When the next frame starts, the first one is drawn (the cloud benchmark reads this).
  requestAnimationFrame(() => { window.vscanFirstFrame = performance.now(); });

  const raycaster = { threshold: pickThreshold(viewer, bounds) };
  window.vscanPickCount = 0;
  window.vscanPicked = null;
  viewer.onClick((ray) => {
    ray.params.Points.threshold = raycaster.threshold;
    const [hit] = ray.intersectObject(points);
    window.vscanPicked = hit ? { cloud_id: record.cloud_id, ...pointFields(points, hit.index) } : null;
    showPickedPoint(window.vscanPicked, record.name);
    viewer.markPicked(hit || null);
    window.vscanPickCount += 1;
  });
  window.vscanViewer = viewer;
  window.vscanView = {
    cloud_id: record.cloud_id,
    shown_points: cloud.count,
    total_points: cloud.total,
    fields: record.fields,
    coloured_by: cloud.instances ? 'instance' : cloud.intensities ? 'intensity' : 'none',
    samples: samplePixels(viewer, points, 16),
  };
}
