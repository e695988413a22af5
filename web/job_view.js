// A job (?job=ID): a campaign's scene and viewpoints coloured by outcome, its scans as they arrive
// (server-sent events), the aligned union growing scan by scan, then the mesh, the uncovered surface
// and the next best views. A model job shows its aligned clouds, mesh and verdict the same way.
import { THREE, Viewer, authHeaders, get, matrixFromRows, setTitle, showPickedRows } from './common.js';
import { addSceneObjects } from './scene_view.js';
import { addMountedRobot, frustumLines } from './robot.js';
import { cloudPoints, parseCloud, pickThreshold, pointFields, showPickedPoint, worldFromRecord } from './cloud_view.js';

// Viewpoint colours by outcome (what the tests look for in the screenshot).
export const OUTCOME_COLOURS = {
  pending: 0x808080, reached: 0x00e000, unreachable: 0xff0000, colliding: 0xffff00,
};
const NEXT_BEST_VIEW_COLOUR = 0xffffff;
const UNCOVERED_COLOUR = 0xff00ff;
const SENSOR_FIELD_COLOUR = 0xffffff;
const PROJECTOR_FIELD_COLOUR = 0xff9900;
const UNION_COLOUR = 0x9ad0ff;
const MESH_COLOUR = 0xc8c8c8;
// A viewpoint's outcome over its steps (one per table angle): the worst one.
const SEVERITY = ['pending', 'reached', 'colliding', 'unreachable'];
// Points drawn over all scans when the page is not told otherwise (?max_points= per cloud).
const POINT_BUDGET = 2000000;

const api = (path) => `api/${path}`;
const jobPath = (id) => `jobs/${encodeURIComponent(id)}`;
const vector = (v) => new THREE.Vector3((v && v.x) || 0, (v && v.y) || 0, (v && v.z) || 0);
const rgb = (hex) => { const c = new THREE.Color(hex); return [c.r, c.g, c.b].map((v) => Math.round(v * 255)); };
// A Matrix4 message ({values: 16, row-major}) or a report's 16 numbers as a three.js matrix.
const matrix16 = (m) => new THREE.Matrix4().set(...(Array.isArray(m) ? m : m.values));

// Reads server-sent events from a fetch (EventSource cannot send the token); calls onEvent(name, data)
// for each, in order, awaiting it.
async function followEvents(path, onEvent) {
  const response = await fetch(path, { headers: authHeaders() });
  if (!response.ok) throw new Error(`${path}: HTTP ${response.status}: ${(await response.text()).trim()}`);
  const reader = response.body.getReader();
  const decoder = new TextDecoder();
  let buffer = '';
  for (;;) {
    const { value, done } = await reader.read();
    if (done) return;
    buffer += decoder.decode(value, { stream: true });
    let end;
    while ((end = buffer.indexOf('\n\n')) >= 0) {
      const block = buffer.slice(0, end);
      buffer = buffer.slice(end + 2);
      let name = 'message';
      const data = [];
      for (const line of block.split('\n')) {
        if (line.startsWith('event:')) name = line.slice(6).trim();
        else if (line.startsWith('data:')) data.push(line.slice(5).trimStart());
      }
      if (data.length > 0) await onEvent(name, JSON.parse(data.join('\n')));
    }
  }
}

// The little-endian binary PLY a model job writes its mesh in (vertex x y z among scalar
// properties, faces as a list of vertex indices) as a three.js geometry.
function parseMeshPly(buffer) {
  const bytes = new Uint8Array(buffer);
  const text = new TextDecoder().decode(bytes.subarray(0, Math.min(bytes.length, 4096)));
  const headerEnd = text.indexOf('end_header\n');
  if (!text.startsWith('ply\n') || headerEnd < 0) throw new Error('mesh.ply: not a PLY file');
  const sizes = { char: 1, uchar: 1, int8: 1, uint8: 1, short: 2, ushort: 2, int16: 2, uint16: 2, int: 4, uint: 4,
    int32: 4, uint32: 4, float: 4, float32: 4, double: 8, float64: 8 };
  const elements = [];
  for (const line of text.slice(0, headerEnd).split('\n')) {
    const words = line.trim().split(/\s+/);
    if (words[0] === 'format' && words[1] !== 'binary_little_endian') throw new Error('mesh.ply: not little-endian');
    if (words[0] === 'element') elements.push({ name: words[1], count: Number(words[2]), properties: [] });
    if (words[0] === 'property') elements[elements.length - 1].properties.push(words.slice(1));
  }
  const view = new DataView(buffer);
  const read = (type, at) => {
    switch (type) {
      case 'char': case 'int8': return view.getInt8(at);
      case 'uchar': case 'uint8': return view.getUint8(at);
      case 'short': case 'int16': return view.getInt16(at, true);
      case 'ushort': case 'uint16': return view.getUint16(at, true);
      case 'int': case 'int32': return view.getInt32(at, true);
      case 'uint': case 'uint32': return view.getUint32(at, true);
      case 'float': case 'float32': return view.getFloat32(at, true);
      default: return view.getFloat64(at, true);
    }
  };
  let at = headerEnd + 'end_header\n'.length;
  let positions = new Float32Array(0);
  const indices = [];
  for (const element of elements) {
    if (element.name === 'vertex') positions = new Float32Array(element.count * 3);
    for (let i = 0; i < element.count; i += 1) {
      for (const property of element.properties) {
        if (property[0] === 'list') {
          const n = read(property[1], at);
          at += sizes[property[1]];
          const corners = [];
          for (let k = 0; k < n; k += 1, at += sizes[property[2]]) corners.push(read(property[2], at));
          for (let k = 1; k + 1 < n; k += 1) indices.push(corners[0], corners[k], corners[k + 1]);
        } else {
          const axis = ['x', 'y', 'z'].indexOf(property[1]);
          if (element.name === 'vertex' && axis >= 0) positions[i * 3 + axis] = read(property[0], at);
          at += sizes[property[0]];
        }
      }
    }
  }
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute('position', new THREE.BufferAttribute(positions, 3));
  geometry.setIndex(new THREE.BufferAttribute(new Uint32Array(indices), 1));
  geometry.computeVertexNormals();
  return geometry;
}

// A camera glyph: a box at the sensor and a frustum towards the target, drawn over everything.
function cameraGlyph(position, target, colour, size) {
  const glyph = new THREE.Group();
  const material = new THREE.MeshBasicMaterial({ color: colour, depthTest: false });
  const box = new THREE.Mesh(new THREE.BoxGeometry(size, size, size), material);
  box.position.copy(position);
  box.renderOrder = 10;
  const forward = target.clone().sub(position).normalize();
  const side = new THREE.Vector3().crossVectors(forward, new THREE.Vector3(0, 0, 1));
  if (side.lengthSq() < 1e-8) side.set(1, 0, 0);
  side.normalize();
  const up = new THREE.Vector3().crossVectors(side, forward);
  const tip = position.clone().addScaledVector(forward, size * 3);
  const corners = [[1, 1], [1, -1], [-1, -1], [-1, 1]].map(([a, b]) => tip.clone()
    .addScaledVector(side, a * size * 1.5).addScaledVector(up, b * size * 1.1));
  const lines = [];
  for (let i = 0; i < 4; i += 1) lines.push(position, corners[i], corners[i], corners[(i + 1) % 4]);
  const frustum = new THREE.LineSegments(new THREE.BufferGeometry().setFromPoints(lines),
    new THREE.LineBasicMaterial({ color: colour, depthTest: false }));
  frustum.renderOrder = 10;
  glyph.add(box, frustum);
  glyph.userData = { box, frustum, position };
  return glyph;
}

class JobView {
  constructor(job, query) {
    this.job = job;
    this.query = query;
    this.viewer = new Viewer();
    this.seenArtifacts = new Set();
    this.cloudsByName = new Map();
    this.scans = new Map();       // scan name -> {points, record, count}
    this.aligned = new Map();     // scan name -> {points, count}
    this.stepOutcomes = new Map();  // step -> outcome
    this.viewpoints = [];         // {index, glyph, outcome}
    this.nextBestViews = [];      // {glyph, view, index}
    this.union = null;
    this.unionPoints = 0;         // the server's count (alignment events)
    this.mesh = null;
    this.uncovered = null;
    this.coverage = null;
    this.events = 0;
    this.ended = false;
    this.history = [];
    this.queue = Promise.resolve();
    this.status = document.createElement('div');
    document.getElementById('content').appendChild(this.status);
    this.pickables = [];
  }

  get spec() { return this.job.campaign || null; }

  maxPointsPerCloud() {
    const asked = Number(this.query.get('max_points'));
    if (asked >= 1) return Math.floor(asked);
    const scans = Math.max(1, this.job.steps_total || 1);
    return Math.max(1000, Math.min(1000000, Math.floor(POINT_BUDGET / scans)));
  }

  async setUp() {
    const bounds = new THREE.Box3();
    const sceneId = await this.sceneId();
    if (sceneId) {
      try {
        const placed = await addSceneObjects(this.viewer, await get(api(`scenes/${encodeURIComponent(sceneId)}`)));
        for (const { mesh } of placed) {
          bounds.expandByObject(mesh);
          // Faint, so that the scans and the model on it show.
          Object.assign(mesh.material, { transparent: true, opacity: 0.25, depthWrite: false });
        }
      } catch (error) {
        this.note(`scene ${sceneId}: ${error.message}`);
      }
    }
    // The campaign's arm, faint, at its home pose until the first scan puts it where that scan was taken.
    if (this.spec && this.spec.mount_id) {
      try {
        this.robot = await addMountedRobot(this.viewer, this.spec.mount_id);
        for (const mesh of this.robot.meshes) {
          Object.assign(mesh.material, { transparent: true, opacity: 0.3, depthWrite: false });
        }
      } catch (error) {
        this.note(`mount ${this.spec.mount_id}: ${error.message}`);
      }
    }
    // The sensor's true field (its preset resolved by the server), drawn at each scan's pose as it arrives.
    if (this.spec) {
      try {
        this.sensor = await get(api(`${jobPath(this.job.job_id)}/sensor`));
      } catch (error) {
        this.note(`sensor: ${error.message}`);
      }
    }
    // Glyphs a few percent of the scene's size (of the model's, for a job without a scene).
    this.glyphSize = bounds.isEmpty() ? 0.02 : Math.max(bounds.getSize(new THREE.Vector3()).length() * 0.04, 0.005);
    const spec = this.spec;
    if (spec && spec.viewpoints) {
      spec.viewpoints.forEach((viewpoint, index) => {
        const glyph = cameraGlyph(vector(viewpoint.position), vector(viewpoint.target), OUTCOME_COLOURS.pending,
          this.glyphSize);
        this.viewer.world.add(glyph);
        this.viewpoints.push({ index, glyph, outcome: 'pending' });
        bounds.expandByPoint(glyph.userData.position);
      });
    }
    if (bounds.isEmpty()) bounds.setFromCenterAndSize(new THREE.Vector3(), new THREE.Vector3(1, 1, 1));
    this.bounds = bounds;
    this.viewer.frame(bounds);
    this.threshold = pickThreshold(this.viewer, bounds);
    this.viewer.onClick((ray) => this.pick(ray));
    window.vscanPickCount = 0;
    window.vscanPicked = null;
  }

  // The scene the job scanned or models (a model job of a campaign: the campaign's).
  async sceneId() {
    if (this.spec) return this.spec.scene_id;
    const model = this.job.model;
    if (!model) return '';
    if (model.scene_id) return model.scene_id;
    if (model.campaign_job_id) {
      try {
        const campaign = await get(api(jobPath(model.campaign_job_id)));
        return campaign.campaign ? campaign.campaign.scene_id : '';
      } catch (error) {
        this.note(error.message);
      }
    }
    return '';
  }

  note(text) {
    const line = document.createElement('div');
    line.textContent = text;
    this.status.appendChild(line);
  }

  // Runs handlers one after another, in the order the events came.
  enqueue(work) {
    this.queue = this.queue.then(work);
    return this.queue;
  }

  async cloudRecord(name) {
    if (!this.cloudsByName.has(name)) {
      const { clouds } = await get(api(`clouds?job=${encodeURIComponent(this.job.job_id)}`));
      for (const record of clouds) this.cloudsByName.set(record.name, record);
    }
    return this.cloudsByName.get(name);
  }

  async fetchCloud(cloudId) {
    return parseCloud(await get(api(`clouds/${encodeURIComponent(cloudId)}?max_points=${this.maxPointsPerCloud()}`),
      'binary'));
  }

  setStepOutcome(step, outcome) {
    this.stepOutcomes.set(step, outcome);
    if (this.viewpoints.length === 0) return;
    const index = step % this.viewpoints.length;
    let worst = 'pending';
    for (const [s, o] of this.stepOutcomes) {
      if (s % this.viewpoints.length === index && SEVERITY.indexOf(o) > SEVERITY.indexOf(worst)) worst = o;
    }
    const viewpoint = this.viewpoints[index];
    viewpoint.outcome = worst;
    viewpoint.glyph.userData.box.material.color.set(OUTCOME_COLOURS[worst]);
    viewpoint.glyph.userData.frustum.material.color.set(OUTCOME_COLOURS[worst]);
  }

  async onArtifact(artifact) {
    if (this.seenArtifacts.has(artifact.artifact_id)) return;
    this.seenArtifacts.add(artifact.artifact_id);
    const name = artifact.name;
    if (artifact.scan || /^scan-.*\.ply$/.test(name)) {
      await this.addScan(artifact);
    } else if (name === 'campaign.json') {
      this.onCampaignReport(await get(this.artifactPath(artifact)));
    } else if (name === 'aligned.ply') {
      if (this.aligned.size === 0) await this.addUnion(artifact);
    } else if (name === 'mesh.ply') {
      await this.addMesh(artifact);
    } else if (name === 'uncovered.ply') {
      await this.addUncovered(artifact);
    } else if (name === 'model.json') {
      await this.onModelReport(await get(this.artifactPath(artifact)));
    }
  }

  artifactPath(artifact, as) {
    return api(`${jobPath(this.job.job_id)}/artifacts/${encodeURIComponent(artifact.artifact_id)}${as ? `?as=${as}&max_points=${this.maxPointsPerCloud()}` : ''}`);
  }

  // The camera's frustum (white) and, for structured light, the projector's (orange) at worldFromSensor,
  // reaching a little past the scene's centre.
  showSensorField(worldFromSensor) {
    if (!this.sensor) return;
    for (const old of this.sensorField || []) this.viewer.world.remove(old);
    const { camera, projector } = this.sensor;
    const position = new THREE.Vector3().setFromMatrixPosition(worldFromSensor);
    const reach = position.distanceTo(this.bounds.getCenter(new THREE.Vector3())) * 1.15;
    const far = Math.max(camera.near, Math.min(camera.far, reach));
    this.sensorField = [frustumLines(worldFromSensor, camera, camera.near, far, SENSOR_FIELD_COLOUR)];
    if (projector) {
      const tx = Math.tan(projector.horizontal_fov_deg * Math.PI / 360);
      const ty = Math.tan(projector.vertical_fov_deg * Math.PI / 360);
      const unit = { width: 2 * tx, height: 2 * ty, fx: 1, fy: 1, cx: tx, cy: ty };
      const worldFromProjector = worldFromSensor.clone().multiply(matrixFromRows(projector.sensor_from_projector));
      this.sensorField.push(frustumLines(worldFromProjector, unit, camera.near, far, PROJECTOR_FIELD_COLOUR));
    }
    for (const lines of this.sensorField) this.viewer.world.add(lines);
    this.sensorPose = worldFromSensor;
  }

  async addScan(artifact) {
    if (this.scans.has(artifact.name)) return;
    const record = await this.cloudRecord(artifact.name);
    if (!record) {
      this.note(`${artifact.name}: no stored cloud`);
      return;
    }
    const cloud = await this.fetchCloud(record.cloud_id);
    const points = cloudPoints(cloud, worldFromRecord(record));
    const scan = { points, record, count: cloud.count };
    this.scans.set(artifact.name, scan);
    this.pickables.push(points);
    const joints = artifact.scan && artifact.scan.achieved_joint_positions;
    if (this.robot && joints && joints.length > 0) {
      await this.robot.setJoints(joints);
      this.robotJoints = joints;
    }
    if (record.world_from_sensor) this.showSensorField(matrixFromRows(record.world_from_sensor));
    if (artifact.scan) {
      const steps = this.viewpoints.length;
      this.setStepOutcome((artifact.scan.rotation_index || 0) * steps + (artifact.scan.viewpoint_index || 0), 'reached');
    }
    // A scan already aligned (its event came first) is shown aligned; else as captured.
    const pending = this.pendingAlignment && this.pendingAlignment.get(artifact.name);
    if (pending) this.placeAligned(artifact.name, pending);
    else this.viewer.world.add(points);
  }

  // Moves a scan into the model frame: model_from_sensor times where the cloud's points are from the sensor.
  placeAligned(name, modelFromSensor) {
    const scan = this.scans.get(name);
    if (!scan) {
      if (!this.pendingAlignment) this.pendingAlignment = new Map();
      this.pendingAlignment.set(name, modelFromSensor);
      return;
    }
    const sensorFromCloud = scan.record.frame === 'sensor' || !scan.record.world_from_sensor
      ? new THREE.Matrix4()
      : new THREE.Matrix4().getInverse(new THREE.Matrix4().set(...scan.record.world_from_sensor.flat()));
    const points = cloudPoints(scan.points.userData.cloud, modelFromSensor.clone().multiply(sensorFromCloud));
    this.viewer.world.remove(scan.points);
    this.pickables = this.pickables.filter((p) => p !== scan.points);
    this.viewer.world.add(points);
    this.pickables.push(points);
    this.aligned.set(name, { points, count: scan.count });
  }

  async onAlignment(alignment) {
    if (alignment.union_points) this.unionPoints = Number(alignment.union_points);
    if (!alignment.aligned || !alignment.pose) return;
    let name = alignment.name;
    if (!this.spec && alignment.cloud_id && !this.scans.has(name)) {
      // A model job's clouds are stored clouds of their own.
      const record = await get(api(`clouds/${encodeURIComponent(alignment.cloud_id)}/record`));
      const cloud = await this.fetchCloud(alignment.cloud_id);
      name = name || record.name;
      this.scans.set(name, { points: cloudPoints(cloud, worldFromRecord(record)), record, count: cloud.count });
    }
    this.placeAligned(name, matrix16(alignment.pose));
  }

  onCampaignReport(report) {
    for (const step of report.steps || []) {
      const outcome = { captured: 'reached', unreachable: 'unreachable', collision: 'colliding' }[step.outcome];
      if (outcome) this.setStepOutcome(step.step, outcome);
    }
  }

  async addUnion(artifact) {
    const cloud = parseCloud(await get(this.artifactPath(artifact, 'cloud'), 'binary'));
    this.union = cloudPoints(cloud, null, 2, UNION_COLOUR);
    this.viewer.world.add(this.union);
    this.pickables.push(this.union);
  }

  async addMesh(artifact) {
    const geometry = parseMeshPly(await get(this.artifactPath(artifact), 'binary'));
    this.mesh = new THREE.Mesh(geometry, new THREE.MeshLambertMaterial({
      color: MESH_COLOUR, transparent: true, opacity: 0.8, side: THREE.DoubleSide,
    }));
    this.mesh.renderOrder = 5;
    this.viewer.world.add(this.mesh);
  }

  async addUncovered(artifact) {
    const cloud = parseCloud(await get(this.artifactPath(artifact, 'cloud'), 'binary'));
    this.uncovered = cloudPoints(cloud, null, 4, UNCOVERED_COLOUR);
    this.uncovered.renderOrder = 6;
    this.viewer.world.add(this.uncovered);
  }

  async onModelReport(report) {
    // A job opened after it ran has no alignment events: the report has the scans' poses.
    for (const scan of (report.alignment && report.alignment.scans) || []) {
      if (scan.aligned && !this.aligned.has(scan.name)) {
        await this.onAlignment({ aligned: true, pose: scan.pose, name: scan.name, cloud_id: scan.cloud_id });
      }
    }
    if (this.union && this.aligned.size > 0) {
      this.viewer.world.remove(this.union);
      this.pickables = this.pickables.filter((p) => p !== this.union);
      this.union = null;
    }
    const evaluation = report.evaluation;
    if (!evaluation) return;
    this.coverage = evaluation.coverage;
    const f = (evaluation.mesh || evaluation.union || {}).f_score;
    this.note(`coverage ${evaluation.coverage.toFixed(3)} at tau ${(evaluation.tau * 1e3).toFixed(2)} mm` +
      (f === undefined ? '' : `, F ${f.toFixed(3)}`) + (this.uncovered ? ' (uncovered surface in magenta)' : ''));
    (evaluation.next_best_views || []).forEach((view, index) => {
      const glyph = cameraGlyph(new THREE.Vector3(...view.position), new THREE.Vector3(...view.target),
        NEXT_BEST_VIEW_COLOUR, this.glyphSize);
      this.viewer.world.add(glyph);
      this.nextBestViews.push({ glyph, view, index });
    });
    if (evaluation.next_best_views_note) this.note(`next best views: ${evaluation.next_best_views_note}`);
  }

  pick(ray) {
    window.vscanPickCount += 1;
    const boxes = this.nextBestViews.map((n) => n.glyph.userData.box);
    const [view] = ray.intersectObjects(boxes);
    if (view) {
      const { view: nbv, index } = this.nextBestViews[boxes.indexOf(view.object)];
      window.vscanPicked = { next_best_view: index, coverage_gain: nbv.coverage_gain,
        coverage_after: nbv.coverage_after, table_angle_deg: nbv.table_angle_deg };
      showPickedRows([['next best view', index + 1], ['adds', `${(nbv.coverage_gain * 100).toFixed(1)} % of the surface`],
        ['coverage after', `${(nbv.coverage_after * 100).toFixed(1)} %`], ['table angle', `${nbv.table_angle_deg} deg`],
        ['look from', nbv.position.map((v) => v.toFixed(3)).join(', ')]]);
      return;
    }
    ray.params.Points.threshold = this.threshold;
    const [hit] = ray.intersectObjects(this.pickables);
    this.viewer.markPicked(hit || null);
    if (!hit) {
      window.vscanPicked = null;
      showPickedRows(null);
      return;
    }
    let label = '';
    for (const [name, scan] of this.scans) if (scan.points === hit.object) label = name;
    for (const [name, aligned] of this.aligned) if (aligned.points === hit.object) label = `${name} (aligned)`;
    if (hit.object === this.union) label = 'aligned.ply';
    window.vscanPicked = { cloud: label, ...pointFields(hit.object, hit.index) };
    showPickedPoint(window.vscanPicked, label);
  }

  async onMessage(name, message) {
    if (name === 'end') {
      this.ended = true;
      return;
    }
    this.events += 1;
    if (message.job) {
      const { artifacts, campaign, model } = message.job;
      Object.assign(this.job, message.job, { artifacts: artifacts || this.job.artifacts,
        campaign: campaign || this.job.campaign, model: model || this.job.model });
      for (const artifact of artifacts || []) await this.onArtifact(artifact);
    }
    const event = message.event;
    if (event) {
      if (/: unreachable, /.test(event.message)) this.setStepOutcome(event.step, 'unreachable');
      else if (/: skipped, /.test(event.message)) this.setStepOutcome(event.step, 'colliding');
      if (event.artifact && event.artifact.artifact_id) await this.onArtifact(event.artifact);
      if (event.alignment) await this.onAlignment(event.alignment);
    }
  }

  update() {
    this.viewer.render();
    const count = (points) => (points ? points.userData.cloud.count : 0);
    let scanPoints = 0;
    for (const [name, scan] of this.scans) if (!this.aligned.has(name) && scan.points.parent) scanPoints += scan.count;
    let alignedPoints = 0;
    for (const aligned of this.aligned.values()) alignedPoints += aligned.count;
    const state = String(this.job.state || '').replace('JOB_STATE_', '');
    setTitle(`vscan: ${this.job.kind} job ${this.job.job_id} ${state}: ${this.job.steps_done || 0} of ` +
      `${this.job.steps_total || 0} steps; ${this.scans.size} scans, ${this.aligned.size} aligned` +
      (this.unionPoints ? ` (union ${this.unionPoints} points)` : ''));
    window.vscanView = {
      job_id: this.job.job_id,
      kind: this.job.kind,
      state,
      ended: this.ended,
      events: this.events,
      max_points_per_cloud: this.maxPointsPerCloud(),
      scans_shown: this.scans.size,
      aligned_shown: this.aligned.size,
      points: { scans: scanPoints, aligned: alignedPoints, union: count(this.union), uncovered: count(this.uncovered) },
      shown_points: scanPoints + alignedPoints + count(this.union) + count(this.uncovered),
      union_points: this.unionPoints,
      robot: this.robot ? { mount_id: this.spec.mount_id, joints: this.robotJoints || null } : null,
      mesh_triangles: this.mesh ? this.mesh.geometry.index.count / 3 : 0,
      mesh_bounds: this.mesh ? (() => {
        this.mesh.geometry.computeBoundingBox();
        const { min, max } = this.mesh.geometry.boundingBox;
        return [min.toArray(), max.toArray()];
      })() : null,
      coverage: this.coverage,
      sensor: this.sensor || null,
      sensor_field: this.sensorPose ? {
        world_from_sensor: this.sensorPose.clone().transpose().toArray(),
        lines: (this.sensorField || []).length,
      } : null,
      viewpoints: this.viewpoints.map(({ index, glyph, outcome }) => ({
        index, outcome, colour: rgb(OUTCOME_COLOURS[outcome]), pixel: this.viewer.pixelOf(glyph.userData.position),
      })),
      next_best_views: this.nextBestViews.map(({ glyph, view }) => ({
        coverage_gain: view.coverage_gain, coverage_after: view.coverage_after, colour: rgb(NEXT_BEST_VIEW_COLOUR),
        pixel: this.viewer.pixelOf(glyph.userData.position),
      })),
      history: this.history,
    };
    const last = this.history[this.history.length - 1];
    const now = [window.vscanView.scans_shown, window.vscanView.aligned_shown, window.vscanView.shown_points];
    if (!last || last.some((v, i) => v !== now[i])) this.history.push(now);
    window.vscanView.history = this.history.map(([scans, aligned, shown]) => ({ scans, aligned, shown }));
  }
}

export async function showJob(id, query) {
  const job = await get(api(jobPath(id)));
  const view = new JobView(job, query);
  await view.setUp();
  for (const artifact of job.artifacts || []) await view.onArtifact(artifact);
  view.update();
  window.vscanViewer = view.viewer;
  window.vscanJobView = view;
  // Follows the job in the background; the page counts as drawn once what the job holds is.
  followEvents(api(`${jobPath(id)}/events`), (name, message) => view.enqueue(async () => {
    await view.onMessage(name, message);
    view.update();
  })).then(() => view.queue).catch((error) => {
    document.getElementById('error').textContent = error.message;
    window.vscanError = error.message;
  }).finally(() => {
    view.update();
    window.vscanView.stream_closed = true;
  });
}
