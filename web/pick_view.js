// A picking job (?picking=JOB_ID): the bin and the pile at each step, from the step's truth file,
// the part taken at that step in orange and the planned tool as an arrow along its approach; the
// steps played one after another (play/pause and a step slider) and the table of steps.
import { THREE, Viewer, get, parseMesh, playerControls, setTitle } from './common.js';
import { addBin, frameFromAbove } from './bin_view.js';

const PART_COLOUR = 0x4a7fb5;
const PICKED_COLOUR = 0xf58231;
const FAILED_TOOL_COLOUR = 0xe6194b;
const STEP_SECONDS = 1.0;  // how long each step shows while playing

function key(name, instance) { return `${name}#${instance + 1}`; }

// The reports' poses: 16 numbers, a 4 x 4 matrix row by row.
function matrixOf(values) { return new THREE.Matrix4().set(...values); }

function stepTable(report, content) {
  const table = document.createElement('table');
  table.id = 'steps';
  const head = table.insertRow();
  for (const heading of ['step', 'parts', 'found', 'outcome', 'picked', 'detail']) {
    head.appendChild(Object.assign(document.createElement('th'), { textContent: heading }));
  }
  for (const step of report.steps) {
    const row = table.insertRow();
    const picked = step.picked_part === undefined ? '' : key(step.picked_part, step.picked_instance);
    for (const cell of [step.step, step.parts_before, step.estimates, step.outcome, picked, step.detail]) {
      row.insertCell().textContent = String(cell);
    }
  }
  content.appendChild(table);
  return table;
}

export async function showPicking(id) {
  const job = await get(`api/jobs/${encodeURIComponent(id)}`);
  setTitle(`vscan: picking ${job.name || job.job_id} (${job.job_id}, ${job.state})`);
  const content = document.getElementById('content');
  const summary = document.createElement('div');
  summary.id = 'summary';
  summary.textContent = job.message;
  content.appendChild(summary);
  const artifacts = new Map((job.artifacts || []).map((a) => [a.name, a.artifact_id]));
  const artifact = (name) => get(`api/jobs/${encodeURIComponent(id)}/artifacts/${encodeURIComponent(artifacts.get(name))}`);
  if (!artifacts.has('picking.json')) {
    const note = document.createElement('div');
    note.textContent = 'picking.json is written when the job ends (reload then)';
    content.appendChild(note);
    window.vscanView = { job_id: job.job_id, state: job.state, steps: 0, step: 0 };
    return;
  }
  const report = await artifact('picking.json');
  const bin = await get(`api/bins/${encodeURIComponent(report.bin_job_id)}`);
  const truths = await Promise.all(report.steps.map((s) => (artifacts.has(s.truth_artifact)
    ? artifact(s.truth_artifact) : null)));

  const viewer = new Viewer();
  const binGroup = await addBin(viewer, bin.bin);
  const types = new Map(bin.types.map((t) => [t.name, t]));
  const geometries = new Map();
  for (const meshId of new Set(bin.types.map((t) => t.mesh_id))) {
    geometries.set(meshId, parseMesh(await get(`api/meshes/${encodeURIComponent(meshId)}`, 'binary')));
  }
  // One mesh per part any step saw.
  const meshes = new Map();
  for (const truth of truths) {
    for (const part of (truth && truth.parts) || []) {
      const label = key(part.part, part.instance ?? 0);
      if (meshes.has(label)) continue;
      const type = types.get(part.part);
      const mesh = new THREE.Mesh(geometries.get(type.mesh_id), new THREE.MeshLambertMaterial({ color: PART_COLOUR }));
      mesh.matrixAutoUpdate = false;
      mesh.userData = { label, scale: type.scale };
      viewer.world.add(mesh);
      meshes.set(label, mesh);
    }
  }
  const arrow = new THREE.ArrowHelper(new THREE.Vector3(0, 0, -1), new THREE.Vector3(), 0.08, PICKED_COLOUR, 0.02, 0.01);
  viewer.world.add(arrow);

  let step = 0;
  function pose(k) {
    const truth = truths[k];
    const s = report.steps[k];
    const picked = s && s.picked_part !== undefined ? key(s.picked_part, s.picked_instance) : null;
    const here = new Map(((truth && truth.parts) || []).map((p) => [key(p.part, p.instance ?? 0), p]));
    for (const [label, mesh] of meshes) {
      const part = here.get(label);
      mesh.visible = Boolean(part);
      if (!part) continue;
      const scale = mesh.userData.scale;
      mesh.matrix.copy(matrixOf(part.world_from_part)).multiply(new THREE.Matrix4().makeScale(scale, scale, scale));
      mesh.material.color.setHex(label === picked ? PICKED_COLOUR : PART_COLOUR);
    }
    arrow.visible = Boolean(s && s.world_from_tool && s.world_from_tool.length === 16);
    if (arrow.visible) {
      const m = matrixOf(s.world_from_tool);
      const tip = new THREE.Vector3().setFromMatrixPosition(m);
      const approach = new THREE.Vector3().setFromMatrixColumn(m, 2).normalize();
      arrow.position.copy(tip).addScaledVector(approach, -0.08);
      arrow.setDirection(approach);
      arrow.setColor(s.outcome === 'picked' ? PICKED_COLOUR : FAILED_TOOL_COLOUR);
    }
    viewer.world.updateMatrixWorld(true);
    return { picked, visible: [...meshes.values()].filter((m) => m.visible).length,
      tool: arrow.visible ? new THREE.Vector3().setFromMatrixPosition(matrixOf(s.world_from_tool)).toArray() : null };
  }

  const { controls, play, slider, label } = playerControls('step', report.steps.length);
  content.appendChild(controls);
  const rows = stepTable(report, content);

  let playing = false;
  let timer = null;
  function show(k) {
    step = Math.max(0, Math.min(k, report.steps.length - 1));
    const shown = report.steps.length ? pose(step) : { visible: 0, picked: null, tool: null };
    slider.value = String(step);
    const s = report.steps[step];
    label.textContent = s ? ` step ${step + 1} of ${report.steps.length}: ${s.outcome}` +
      (shown.picked ? ` ${shown.picked}` : '') : ' no steps';
    play.textContent = playing ? 'pause' : 'play';
    [...rows.rows].forEach((row, i) => { row.style.fontWeight = i === step + 1 ? 'bold' : ''; });
    window.vscanView.step = step;
    viewer.render();
    return shown;
  }
  function advance() {
    if (step + 1 >= report.steps.length) {
      playing = false;
      timer = null;
      show(step);
      return;
    }
    show(step + 1);
    timer = setTimeout(advance, STEP_SECONDS * 1000);
  }
  play.addEventListener('click', () => {
    playing = !playing;
    clearTimeout(timer);
    if (playing) {
      if (step >= report.steps.length - 1) step = -1;
      advance();
    } else {
      show(step);
    }
  });
  slider.addEventListener('input', () => {
    playing = false;
    clearTimeout(timer);
    show(Number(slider.value));
  });

  window.vscanViewer = viewer;
  window.vscanView = {
    job_id: job.job_id, state: job.state, bin_job_id: report.bin_job_id, steps: report.steps.length, step: 0,
    parts: meshes.size, picked: report.picked, end: report.end ?? null,
  };
  // Shows step k (paused) and returns what it draws: parts visible, the part picked, the tool's tip.
  window.vscanSeek = (k) => {
    playing = false;
    clearTimeout(timer);
    return { step: k, ...show(k) };
  };
  pose(0);
  const bounds = new THREE.Box3().setFromObject(binGroup);
  for (const mesh of meshes.values()) if (mesh.visible) bounds.expandByObject(mesh);
  frameFromAbove(viewer, bounds);
  show(0);
}
