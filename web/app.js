// The vscan web view: picks the view from the query (?scene=ID, ...) and reads its data over the
// read-only API with the token from the URL fragment (#token=...). Without a query it lists what
// there is to see. window.vscanReady turns true once the view is drawn (or has failed, with
// window.vscanError), which is what the browser tests wait for.
import { get, setTitle, showError } from './common.js';
import { showScene } from './scene_view.js';
import { listDatasets, showDataset } from './dataset_view.js';
import { showJob } from './job_view.js';
import { showCloud } from './cloud_view.js';
import { showBin } from './bin_view.js';
import { showPicking } from './pick_view.js';

function link(query, text) {
  const item = document.createElement('li');
  const a = document.createElement('a');
  a.href = `?${query}${location.hash}`;
  a.textContent = text;
  item.appendChild(a);
  return item;
}

async function listScenes() {
  const { scenes } = await get('api/scenes');
  const list = document.createElement('ul');
  for (const scene of scenes) {
    list.appendChild(link(`scene=${encodeURIComponent(scene.scene_id)}`,
      `${scene.name || scene.scene_id} (${scene.scene_id}, ${scene.object_count} objects)`));
  }
  setTitle(`vscan: ${scenes.length} scenes`);
  document.getElementById('content').appendChild(list);
}

// The view that shows a job of kind, as `vscan view JOB` chooses it.
function viewOfJobKind(kind) {
  return { bin_fill: 'bin', dataset: 'dataset', picking: 'picking' }[kind] || 'job';
}

// ?job=ID for any kind: bin fills, dataset and picking jobs have views of their own.
async function showAnyJob(id, query) {
  const { kind } = await get(`api/jobs/${encodeURIComponent(id)}`);
  const view = viewOfJobKind(kind);
  if (view !== 'job') {
    history.replaceState(null, '', `?${view}=${encodeURIComponent(id)}${location.hash}`);
    return VIEWS[view](id, new URLSearchParams(location.search));
  }
  return showJob(id, query);
}

async function listJobs() {
  const { jobs } = await get('api/jobs?limit=20');
  const heading = document.createElement('div');
  heading.textContent = `${jobs.length} recent jobs`;
  const list = document.createElement('ul');
  for (const job of jobs) {
    const view = viewOfJobKind(job.kind);
    list.appendChild(link(`${view}=${encodeURIComponent(job.job_id)}`, `${job.name || job.job_id} (${job.kind}, ` +
      `${job.state}, ${job.steps_done} of ${job.steps_total} steps, ${job.job_id})`));
  }
  document.getElementById('content').append(heading, list);
}

// Each view by the query parameter that names what it shows.
const VIEWS = {
  scene: showScene,
  dataset: showDataset,
  job: showAnyJob,
  cloud: showCloud,
  bin: showBin,
  picking: showPicking,
};

async function main() {
  try {
    const query = new URLSearchParams(location.search);
    // The query's first key that names a view: ?dataset=ID&scene=... is the dataset's view.
    const name = [...query.keys()].find((key) => Object.hasOwn(VIEWS, key));
    if (name) await VIEWS[name](query.get(name), query); else { await listScenes(); await listDatasets(); await listJobs(); }
  } catch (error) {
    showError(error.message);
    window.vscanError = error.message;
  } finally {
    window.vscanReady = true;
  }
}

main();
