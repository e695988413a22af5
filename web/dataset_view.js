// A dataset job (?dataset=JOB_ID, and &scene=N&view=N for one view): its complete scenes and their
// views, and one view drawn in 2D: the grey image with overlays to toggle (depth in false colour,
// visible masks and ground-truth boxes in the instance palette, each pose as projected axes). A
// click reports the pixel's depth and the object seen there.
import { fillSwatchTable, get, instanceColour, setTitle, showPickedRows } from './common.js';

const OVERLAYS = ['grey', 'depth', 'masks', 'boxes', 'axes'];
const DEFAULT_OVERLAYS = ['grey', 'masks', 'boxes', 'axes'];
// How much of an object's colour a visible-mask pixel takes; the rest is what lies under it.
const MASK_ALPHA = 0.5;
// Depth colours from near to far.
const DEPTH_STOPS = [[48, 18, 59], [40, 150, 230], [60, 220, 110], [240, 200, 40], [200, 30, 20]];
const AXIS_COLOURS = ['#ff3030', '#30ff30', '#3080ff'];

function fileUrl(jobId, path) {
  return `api/datasets/${encodeURIComponent(jobId)}/files/${path.split('/').map(encodeURIComponent).join('/')}`;
}

// An 8- or 16-bit grey PNG as the dataset writes them (not interlaced), its samples exact: the
// browser's own decoder would give 8 bits of a 16-bit depth.
async function decodeGreyPng(buffer) {
  const bytes = new Uint8Array(buffer);
  const signature = [0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a];
  if (signature.some((b, i) => bytes[i] !== b)) throw new Error('not a PNG');
  const view = new DataView(buffer);
  let header = null;
  const idat = [];
  for (let at = 8; at + 8 <= bytes.length;) {
    const length = view.getUint32(at);
    const type = String.fromCharCode(...bytes.subarray(at + 4, at + 8));
    const body = bytes.subarray(at + 8, at + 8 + length);
    if (type === 'IHDR') {
      header = { width: view.getUint32(at + 8), height: view.getUint32(at + 12), bits: body[8], colour: body[9],
        interlace: body[12] };
    } else if (type === 'IDAT') {
      idat.push(body);
    } else if (type === 'IEND') {
      break;
    }
    at += 12 + length;
  }
  if (!header || header.colour !== 0 || (header.bits !== 8 && header.bits !== 16) || header.interlace !== 0) {
    throw new Error('PNG: only 8- and 16-bit grey images are read');
  }
  const { width, height, bits } = header;
  const stream = new Blob(idat).stream().pipeThrough(new DecompressionStream('deflate'));
  const raw = new Uint8Array(await new Response(stream).arrayBuffer());
  const bpp = bits / 8;
  const stride = width * bpp;
  if (raw.length < height * (stride + 1)) throw new Error('PNG: image data too short');
  const data = bits === 16 ? new Uint16Array(width * height) : new Uint8Array(width * height);
  let prev = new Uint8Array(stride);
  let line = new Uint8Array(stride);
  for (let y = 0; y < height; y += 1) {
    const filter = raw[y * (stride + 1)];
    line.set(raw.subarray(y * (stride + 1) + 1, (y + 1) * (stride + 1)));
    for (let x = 0; x < stride; x += 1) {
      const a = x >= bpp ? line[x - bpp] : 0;
      const b = prev[x];
      const c = x >= bpp ? prev[x - bpp] : 0;
      let add = 0;
      if (filter === 1) add = a;
      else if (filter === 2) add = b;
      else if (filter === 3) add = (a + b) >> 1;
      else if (filter === 4) {
        const p = a + b - c;
        const pa = Math.abs(p - a); const pb = Math.abs(p - b); const pc = Math.abs(p - c);
        add = pa <= pb && pa <= pc ? a : (pb <= pc ? b : c);
      }
      line[x] = (line[x] + add) & 0xff;
    }
    for (let x = 0; x < width; x += 1) {
      data[y * width + x] = bits === 16 ? (line[2 * x] << 8) | line[2 * x + 1] : line[x];
    }
    [prev, line] = [line, prev];
  }
  return { width, height, bits, data };
}

function colourOf(object) {
  const c = instanceColour(object.instance_id);
  return [c.r, c.g, c.b].map((v) => Math.round(v * 255));
}

function depthColour(t) {
  const x = Math.min(Math.max(t, 0), 1) * (DEPTH_STOPS.length - 1);
  const i = Math.min(Math.floor(x), DEPTH_STOPS.length - 2);
  const f = x - i;
  return DEPTH_STOPS[i].map((v, k) => Math.round(v + (DEPTH_STOPS[i + 1][k] - v) * f));
}

// The grey value shown white: the 99.5th percentile of the lit pixels, so that a few glints do not
// darken the rest.
function greyWhite(grey) {
  const counts = new Uint32Array(65536);
  let lit = 0;
  for (const g of grey.data) {
    if (g > 0) { counts[g] += 1; lit += 1; }
  }
  if (lit === 0) return 1;
  let seen = 0;
  for (let g = 1; g < counts.length; g += 1) {
    seen += counts[g];
    if (seen >= lit * 0.995) return g;
  }
  return 65535;
}

// Where the camera (cam_K, BOP's pixel centres at whole coordinates) sees a point of its frame (mm).
function project(K, p) {
  return [K[0] * p[0] / p[2] + K[2], K[4] * p[1] / p[2] + K[5]];
}

function link(query, text) {
  const a = document.createElement('a');
  a.href = `?${query}${location.hash}`;
  a.textContent = text;
  return a;
}

function checkbox(name, checked, onChange) {
  const label = document.createElement('label');
  const input = document.createElement('input');
  input.type = 'checkbox';
  input.id = `overlay-${name}`;
  input.checked = checked;
  input.addEventListener('change', () => onChange(input.checked));
  label.append(input, ` ${name} `);
  return label;
}

// The page's state for one dataset job: its listing, the view shown and its decoded images.
class DatasetPage {
  constructor(dataset, query) {
    this.dataset = dataset;
    const asked = query.get('overlays');
    this.overlays = new Set(asked === null ? DEFAULT_OVERLAYS : asked.split(',').filter((o) => OVERLAYS.includes(o)));
    this.shown = null;
    window.vscanDrawCount = 0;
    window.vscanPickCount = 0;
  }

  // The dataset, its scenes with links to each view, the overlay switches and the view's objects.
  build() {
    const d = this.dataset;
    const count = d.scene_count === null ? '?' : d.scene_count;
    setTitle(`vscan: dataset ${d.name || d.job_id} (${d.job_id}, ${d.state}, ${d.scenes_complete} of ${count} scenes)`);
    const content = document.getElementById('content');
    const scenes = document.createElement('div');
    scenes.id = 'scenes';
    scenes.style.maxHeight = '30vh';
    scenes.style.overflowY = 'auto';
    for (const split of d.splits) {
      for (const scene of split.scenes) {
        const line = document.createElement('div');
        line.append(`${split.split}/${scene.scene_id}: views `);
        for (const view of scene.views) {
          const a = link(this.query(scene.scene_id, view), String(view));
          a.addEventListener('click', (event) => {
            event.preventDefault();
            history.pushState(null, '', `?${this.query(scene.scene_id, view)}${location.hash}`);
            this.showView(scene.scene_id, view).catch((error) => this.fail(error));
          });
          line.append(a, ' ');
        }
        scenes.appendChild(line);
      }
      if (split.scenes.length === 0) scenes.append('no scene is complete yet');
    }
    if (d.splits.some((s) => s.more)) scenes.append(' (more scenes: ?after=, ?limit= of the API)');
    const switches = document.createElement('div');
    switches.id = 'overlays';
    for (const name of OVERLAYS) {
      switches.appendChild(checkbox(name, this.overlays.has(name), (on) => {
        if (on) this.overlays.add(name); else this.overlays.delete(name);
        if (this.shown) history.replaceState(null, '', `?${this.query(this.shown.scene_id, this.shown.view)}${location.hash}`);
        this.draw();
      }));
    }
    this.table = document.createElement('table');
    content.append(scenes, switches, this.table);
    window.addEventListener('popstate', () => {
      const query = new URLSearchParams(location.search);
      if (query.has('scene') && query.has('view')) {
        this.showView(query.get('scene'), query.get('view')).catch((error) => this.fail(error));
      }
    });
  }

  fail(error) {
    document.getElementById('error').textContent = error.message;
    console.error(error.message);
  }

  query(sceneId, view) {
    const overlays = [...this.overlays].join(',');
    return `dataset=${encodeURIComponent(this.dataset.job_id)}&scene=${encodeURIComponent(sceneId)}` +
      `&view=${encodeURIComponent(view)}&overlays=${overlays}`;
  }

  async showView(sceneId, view) {
    const id = this.dataset.job_id;
    const shown = await get(`api/datasets/${encodeURIComponent(id)}/scenes/${encodeURIComponent(sceneId)}` +
      `/views/${encodeURIComponent(view)}`);
    const load = (path) => (path ? get(fileUrl(id, path), 'binary').then(decodeGreyPng) : Promise.resolve(null));
    const [grey, depth, instances] = await Promise.all([load(shown.images.gray), load(shown.images.depth),
      load(shown.images.instances)]);
    const { width, height } = shown.camera;
    for (const image of [grey, depth, instances]) {
      if (image && (image.width !== width || image.height !== height)) throw new Error('image size differs from the camera');
    }
    this.shown = { ...shown, grey, depth, instances, greyWhite: grey ? greyWhite(grey) : 1 };
    const error = document.getElementById('error');
    error.textContent = '';
    this.showObjects();
    showPickedRows(null);
    window.vscanPicked = undefined;
    this.draw();
  }

  showObjects() {
    fillSwatchTable(this.table, ['gt', 'obj_id', 'instance', 'visib_fract', 'bbox_visib'], this.shown.objects,
      (object) => `rgb(${colourOf(object).join(',')})`,
      (object) => [object.gt_index, object.obj_id, object.instance_id, Number(object.visib_fract).toFixed(3),
        JSON.stringify(object.bbox_visib)]);
  }

  // Draws the view at a whole-number scale that fits the right of the page (at most 4 times).
  draw() {
    const s = this.shown;
    if (!s) return;
    const { width, height } = s.camera;
    const container = document.getElementById('view');
    const fit = Math.min((container.clientWidth * 0.55 - 16) / width, (container.clientHeight - 16) / height);
    const scale = fit >= 1 ? Math.min(4, Math.floor(fit)) : Math.max(fit, 0.1);
    if (!this.canvas) {
      this.canvas = document.createElement('canvas');
      this.canvas.id = 'dataset-canvas';
      this.canvas.style.position = 'absolute';
      this.canvas.style.right = '8px';
      this.canvas.style.top = '8px';
      this.canvas.addEventListener('click', (event) => this.pick(event));
      container.appendChild(this.canvas);
    }
    const canvas = this.canvas;
    canvas.width = Math.round(width * scale);
    canvas.height = Math.round(height * scale);

    const pixels = new ImageData(width, height);
    const out = pixels.data;
    for (let i = 0; i < width * height; i += 1) out[4 * i + 3] = 255;
    if (this.overlays.has('grey') && s.grey) {
      for (let i = 0; i < width * height; i += 1) {
        const g = Math.min(255, Math.round(s.grey.data[i] * 255 / s.greyWhite));
        out[4 * i] = g; out[4 * i + 1] = g; out[4 * i + 2] = g;
      }
    }
    let near = Infinity;
    let far = 0;
    for (const d of s.depth.data) {
      if (d > 0) { near = Math.min(near, d); far = Math.max(far, d); }
    }
    if (this.overlays.has('depth')) {
      for (let i = 0; i < width * height; i += 1) {
        const d = s.depth.data[i];
        if (d === 0) continue;
        const c = depthColour(far > near ? (d - near) / (far - near) : 0);
        out[4 * i] = c[0]; out[4 * i + 1] = c[1]; out[4 * i + 2] = c[2];
      }
    }
    const colours = s.objects.map(colourOf);
    const maskPixels = s.objects.map(() => 0);
    for (let i = 0; i < width * height; i += 1) {
      const k = s.instances.data[i] - 1;
      if (k < 0 || k >= colours.length) continue;
      maskPixels[k] += 1;
      if (!this.overlays.has('masks')) continue;
      for (let c = 0; c < 3; c += 1) {
        out[4 * i + c] = Math.round(MASK_ALPHA * colours[k][c] + (1 - MASK_ALPHA) * out[4 * i + c]);
      }
    }
    const image = document.createElement('canvas');
    image.width = width;
    image.height = height;
    image.getContext('2d').putImageData(pixels, 0, 0);
    const ctx = canvas.getContext('2d');
    ctx.imageSmoothingEnabled = false;
    ctx.drawImage(image, 0, 0, canvas.width, canvas.height);

    // Ground-truth boxes around the visible pixels (BOP's [x, y, w, h]: w = max x - min x), their
    // outer edge on the outer edge of those pixels, two canvas pixels wide, labelled obj_id/gt.
    const boxes = [];
    if (this.overlays.has('boxes')) {
      ctx.font = '11px sans-serif';
      ctx.textBaseline = 'top';
      s.objects.forEach((object, k) => {
        const [x, y, w, h] = object.bbox_visib;
        if (x < 0 || y < 0) return;
        const rect = [x * scale, y * scale, (x + w + 1) * scale, (y + h + 1) * scale].map(Math.round);
        const colour = `rgb(${colours[k].join(',')})`;
        ctx.lineWidth = 2;
        ctx.strokeStyle = colour;
        ctx.strokeRect(rect[0] + 1, rect[1] + 1, rect[2] - rect[0] - 2, rect[3] - rect[1] - 2);
        const text = `obj ${object.obj_id} #${object.gt_index}`;
        const textWidth = Math.ceil(ctx.measureText(text).width) + 4;
        const top = rect[1] >= 14 ? rect[1] - 14 : rect[1] + 2;
        const left = rect[0] + (rect[1] >= 14 ? 0 : 2);
        ctx.fillStyle = 'rgba(0, 0, 0, 0.7)';
        ctx.fillRect(left, top, textWidth, 13);
        ctx.fillStyle = colour;
        ctx.fillText(text, left + 2, top + 1);
        boxes.push({ gt_index: object.gt_index, obj_id: object.obj_id, rect, colour: colours[k] });
      });
    }

    // Each pose: the model's origin and axes (x red, y green, z blue) projected with cam_K, the axes
    // as long as 0.4 of the object's full box diagonal.
    const K = s.camera.cam_K;
    const origins = s.objects.map((object) => {
      const t = object.cam_t_m2c;
      return t[2] > 0 ? project(K, t) : null;
    });
    if (this.overlays.has('axes')) {
      s.objects.forEach((object, k) => {
        const t = object.cam_t_m2c;
        const R = object.cam_R_m2c;
        if (!origins[k]) return;
        const [, , bw, bh] = object.bbox_obj;
        const length = 0.4 * Math.max(Math.hypot(bw, bh), 10) * t[2] / K[0];
        const at = (p) => p.map((v) => (v + 0.5) * scale);
        const o = at(origins[k]);
        ctx.lineWidth = 2;
        for (let axis = 0; axis < 3; axis += 1) {
          const end = [0, 1, 2].map((r) => t[r] + R[3 * r + axis] * length);
          if (end[2] <= 0) continue;
          const e = at(project(K, end));
          ctx.strokeStyle = AXIS_COLOURS[axis];
          ctx.beginPath();
          ctx.moveTo(o[0], o[1]);
          ctx.lineTo(e[0], e[1]);
          ctx.stroke();
        }
        ctx.fillStyle = '#ffffff';
        ctx.beginPath();
        ctx.arc(o[0], o[1], 2.5, 0, 2 * Math.PI);
        ctx.fill();
      });
    }

    const rect = canvas.getBoundingClientRect();
    window.vscanDrawCount += 1;
    window.vscanView = {
      job_id: this.dataset.job_id,
      scene_id: s.scene_id,
      view: s.view,
      width,
      height,
      scale,
      // The canvas's top left corner in the page (CSS pixels): image pixel (u, v) covers
      // [left + u * scale, left + (u + 1) * scale) and the same in y.
      canvas: [rect.left, rect.top],
      overlays: OVERLAYS.filter((o) => this.overlays.has(o)),
      greyWhite: s.greyWhite,
      maskAlpha: MASK_ALPHA,
      depth: { near, far },
      boxes,
      objects: s.objects.map((object, k) => ({
        gt_index: object.gt_index,
        obj_id: object.obj_id,
        instance_id: object.instance_id,
        colour: colours[k],
        mask_pixels: maskPixels[k],
        origin: origins[k],
      })),
    };
  }

  // Reports the clicked pixel: its depth (mm, from the depth image and depth_scale) and the
  // object whose visible mask holds it, with that object's ground truth.
  pick(event) {
    const s = this.shown;
    const scale = window.vscanView.scale;
    const u = Math.floor(event.offsetX / scale);
    const v = Math.floor(event.offsetY / scale);
    const { width, height } = s.camera;
    if (u < 0 || v < 0 || u >= width || v >= height) return;
    const raw = s.depth.data[v * width + u];
    const object = s.objects[s.instances.data[v * width + u] - 1] || null;
    const depthMm = raw > 0 ? raw * s.camera.depth_scale : null;
    window.vscanPicked = {
      u, v, depth_raw: raw, depth_mm: depthMm,
      object: object && {
        gt_index: object.gt_index, obj_id: object.obj_id, instance_id: object.instance_id,
        cam_R_m2c: object.cam_R_m2c, cam_t_m2c: object.cam_t_m2c, bbox_obj: object.bbox_obj,
        bbox_visib: object.bbox_visib, visib_fract: object.visib_fract,
      },
    };
    const rows = [['pixel', `${u}, ${v}`], ['depth', depthMm === null ? 'none' : `${Number(depthMm.toFixed(3))} mm`]];
    if (object) {
      rows.push(['object', `obj_id ${object.obj_id}, gt ${object.gt_index}, instance ${object.instance_id}`],
        ['visib_fract', String(object.visib_fract)], ['bbox_visib', JSON.stringify(object.bbox_visib)],
        ['cam_t_m2c (mm)', object.cam_t_m2c.map((x) => x.toFixed(2)).join(', ')],
        ['cam_R_m2c', object.cam_R_m2c.map((x) => x.toFixed(4)).join(', ')]);
    } else {
      rows.push(['object', 'none (no visible mask here)']);
    }
    showPickedRows(rows);
    window.vscanPickCount += 1;
  }
}

export async function showDataset(jobId, query) {
  const dataset = await get(`api/datasets/${encodeURIComponent(jobId)}`);
  const page = new DatasetPage(dataset, query);
  page.build();
  if (query.has('scene') && query.has('view')) await page.showView(query.get('scene'), query.get('view'));
}

// The dataset jobs, for the page without a view.
export async function listDatasets() {
  const { datasets } = await get('api/datasets');
  const heading = document.createElement('div');
  heading.textContent = `${datasets.length} datasets`;
  const list = document.createElement('ul');
  for (const d of datasets) {
    const item = document.createElement('li');
    const count = d.scene_count === null ? '?' : d.scene_count;
    item.appendChild(link(`dataset=${encodeURIComponent(d.job_id)}`,
      `${d.name || d.job_id} (${d.job_id}, ${d.state}, ${d.scenes_complete} of ${count} scenes)`));
    list.appendChild(item);
  }
  document.getElementById('content').append(heading, list);
}
