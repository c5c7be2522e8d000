// mrr explore: the page. Everything it shows comes from the JSON API (docs/explore.md); the
// server renders, this only asks and draws. No framework, no build step.
'use strict';

const $ = (sel, root = document) => root.querySelector(sel);
const $$ = (sel, root = document) => Array.from(root.querySelectorAll(sel));

const state = {
  info: null,
  params: {},          // frame parameters (the command line's option names)
  reports: {cpu: null, gpu: null},
  port: false,
  layer: 'final',
  layers: [],
  pixel: null,         // [x, y] of the probed pixel
  probe: null,         // the oracle's (or the one path's) probe of it, for the footprint
  seq: 0,              // the latest render request; older answers are dropped
  abort: null,         // aborts the frame requests of the render in flight (the server then cancels it)
  view: Math.random().toString(36).slice(2, 10),  // this page's view: a newer frame for it supersedes an older one
  zoom: 1,
};

class ApiError extends Error {
  constructor(status, body) {
    super(body && body.error ? body.error : 'HTTP ' + status);
    this.status = status;
    this.parameter = body ? body.parameter : null;
    this.body = body;
  }
}

async function api(path, signal) {
  const r = await fetch(path, signal ? {signal} : {});
  const type = r.headers.get('content-type') || '';
  const body = type.startsWith('application/json') ? await r.json() : null;
  if (!r.ok) throw new ApiError(r.status, body);
  return body;
}

function query(extra = {}) {
  const q = new URLSearchParams();
  const all = Object.assign({}, state.params, extra);
  for (const [k, v] of Object.entries(all)) {
    if (v === undefined || v === null || v === '') continue;
    if (Array.isArray(v)) v.forEach((x) => q.append(k, x));
    else q.set(k, v);
  }
  return q.toString();
}

const fmt = (v, digits = 3) => (typeof v === 'number' ? (Number.isInteger(v) ? String(v) : v.toPrecision(digits)) : String(v));

// ---------------------------------------------------------------------------------------------
// Busy state and progress.

let pending = 0, poller = null;
function busy(delta) {
  pending += delta;
  document.body.dataset.busy = pending > 0 ? '1' : '0';
  if (pending > 0 && !poller) {
    $('#progress').classList.add('working');
    poller = setInterval(pollProgress, 150);
  } else if (pending === 0 && poller) {
    clearInterval(poller);
    poller = null;
    $('#progress').classList.remove('working');
    if (!$('#progress').classList.contains('error')) $('#progress-text').textContent = state.message || '';
  }
}

async function pollProgress() {
  try {
    const p = await api('/api/progress');
    if (pending === 0) return;
    $('#progress-text').textContent = p.busy
      ? `rendering ${p.job}${p.stage ? ' — ' + p.stage : ''} (${Math.round(p.elapsed_ms)} ms)` +
        (p.queued > 1 ? `, ${p.queued - 1} waiting` : '')
      : 'preparing images…';
  } catch (e) { /* the next poll tries again */ }
}

function say(text, error = false) {
  $('#progress-text').textContent = text;
  $('#progress').classList.toggle('error', error);
}

// ---------------------------------------------------------------------------------------------
// Controls → parameters.

function readControls() {
  const p = state.params;
  for (const el of $$('[data-param]')) p[el.dataset.param] = el.value;
  p.never_slower = $('#never_slower').checked ? 'on' : 'off';
  if ($('#effect_only').checked) p.effect_only = '1';  // SPEC §12.3: the ablation's effect-only arm
  else delete p.effect_only;
  p.disable_level = $$('.enabled').filter((el) => !el.checked).map((el) => el.dataset.level);
}

function levelList(cls) {
  return $$('.' + cls).sort((a, b) => a.dataset.level - b.dataset.level).map((el) => el.value).join(',');
}

function fillControls(report) {
  $('#tau_n').value = report.edges.tau_n.toFixed(3).replace(/0+$/, '').replace(/\.$/, '');
  $('#tau_n_slider').value = report.edges.tau_n;
  $('#tau_z').value = +report.edges.tau_z.toFixed(4);
  $('#tau_z_slider').value = report.edges.tau_z;
  $('#samples').value = report.samples;
  for (const lv of report.levels) {
    const s = $(`.sigma2[data-level="${lv.level}"]`), w = $(`.weight[data-level="${lv.level}"]`);
    if (s) s.value = +lv.sigma2.toFixed(3);
    if (w) w.value = +lv.weight.toFixed(3);
  }
}

function changed(ev) {
  const el = ev.target;
  $$('.invalid').forEach((x) => x.classList.remove('invalid'));
  if (el.id === 'tau_n_slider') $('#tau_n').value = el.value;
  if (el.id === 'tau_z_slider') $('#tau_z').value = el.value;
  if (el.classList.contains('sigma2')) state.params.sigma2 = levelList('sigma2');
  if (el.classList.contains('weight')) state.params.weights = levelList('weight');
  if (el.id === 'effect' || el.id === 'method') {  // their own defaults (Table 1)
    delete state.params.sigma2;
    delete state.params.weights;
    if (el.id === 'effect') state.params.samples = '';
    $('#samples').value = '';
  }
  if (el.id === 'scene') clearCamera();
  if (el.id === 'gaze_click' && !el.checked) delete state.params.gaze;  // off: no gaze, mrr's masks again
  readControls();
  if (el.id === 'effect') delete state.params.samples;
  render();
}

// ---------------------------------------------------------------------------------------------
// The camera: orbit about the target and dolly along the view, from the frame's own camera.

function clearCamera() {
  delete state.params.eye;
  delete state.params.target;
  delete state.params.fov;
}

function moveCamera(yawStep, pitchStep, dolly) {
  const cam = state.reports.cpu && state.reports.cpu.camera;
  if (!cam) return;
  const [ex, ey, ez] = cam.eye, [tx, ty, tz] = cam.target;
  let dx = ex - tx, dy = ey - ty, dz = ez - tz;
  let r = Math.hypot(dx, dy, dz);
  let yaw = Math.atan2(dx, dz), pitch = Math.asin(Math.max(-1, Math.min(1, dy / r)));
  yaw += yawStep * Math.PI / 12;
  pitch = Math.max(-1.4, Math.min(1.4, pitch + pitchStep * Math.PI / 18));
  r *= dolly;
  dx = r * Math.cos(pitch) * Math.sin(yaw);
  dy = r * Math.sin(pitch);
  dz = r * Math.cos(pitch) * Math.cos(yaw);
  const v = (a) => a.map((x) => x.toFixed(4)).join(',');
  state.params.eye = v([tx + dx, ty + dy, tz + dz]);
  state.params.target = v([tx, ty, tz]);
  state.params.fov = cam.yfov_degrees.toFixed(3);
  render();
}

// ---------------------------------------------------------------------------------------------
// Rendering a frame: the report of each path, then the layer, then the probe.

// The server's work budget (/api/info budget): the samples knob stops at the most that
// fit at this frame's size (max_samples of the frame, or of the 400 that refused it).
function showSamplesLimit(most) {
  const b = state.info && state.info.budget;
  if (!b || most === undefined || most === null) return;
  $('#samples').max = String(Math.max(1, most));
  $('#samples_limit').textContent = most > 0
    ? `at most ${most} samples at this size (the server's budget: ${b.budget_m} M sample-pixels a request)`
    : `this size is over the server's budget (${b.budget_m} M sample-pixels a request) even at 1 sample`;
}

async function render() {
  const seq = ++state.seq;
  if (state.abort) state.abort.abort();  // the older frame's requests: the server stops their render
  const abort = state.abort = new AbortController();
  busy(+1);
  document.body.dataset.state = 'rendering';
  say('rendering…');
  try {
    const q = query() + '&view=' + state.view;
    const cpu = await api('/api/frame?' + q + '&path=cpu', abort.signal);
    if (seq !== state.seq) return;
    let gpu = null;
    if (state.port) gpu = await api('/api/frame?' + q + '&path=gpu', abort.signal);
    if (seq !== state.seq) return;
    showSamplesLimit(cpu.explore.max_samples);
    state.reports = {cpu, gpu};
    fillControls(cpu);
    showStats();
    fillLayers(cpu.explore.layers);
    await showLayer(seq);
    if (seq !== state.seq) return;
    if (state.pixel) await probe();
    if (seq !== state.seq) return;
    state.message = `rendered in ${Math.round(cpu.explore.render_wall_ms)} ms (oracle)` +
        (gpu ? `, ${Math.round(gpu.explore.render_wall_ms)} ms (port)` : '') + '; cached frames answer at once';
    say(state.message);
    document.body.dataset.renders = String(+document.body.dataset.renders + 1);
    document.body.dataset.state = 'ready';
  } catch (e) {
    if (seq !== state.seq) return;
    document.body.dataset.state = 'error';
    if (e.body) showSamplesLimit(e.body.max_samples);
    say((e.parameter ? `bad ${e.parameter}: ` : '') + e.message, true);
    if (e.parameter) {
      const el = document.getElementById(e.parameter);
      if (el) el.classList.add('invalid');
    }
  } finally {
    busy(-1);
  }
}

function showStats() {
  const {cpu, gpu} = state.reports;
  const rows = [];
  const both = (label, f, id) => rows.push([label, f(cpu), gpu ? f(gpu) : null, id]);
  $('#summary').textContent = `${cpu.scene.split('/').pop()} · ${cpu.effect} · ${cpu.method} · ${cpu.width}×${cpu.height} · ${cpu.samples} samples`;
  both('never slower', (r) => {
    if (!r.never_slower) {
      const w = r.explore.rule_off;
      if (!w) return 'off';
      return `off: it would ${w.would_fall_back ? 'fall back to full' : 'keep mrr'}` +
        ` (predicted ${fmt(w.predicted_mrr_ms)} vs ${fmt(w.predicted_full_ms)} ms full)`;
    }
    const n = r.never_slower;
    return (n.fell_back_to_full ? 'fell back to full' : 'kept mrr') +
      ` (predicted ${fmt(n.predicted_mrr_ms)} vs ${fmt(n.predicted_full_ms)} ms full)`;
  }, 'never-slower');
  both('ideal speedup', (r) => fmt(r.ideal_speedup) + '×', 'ideal-speedup');
  both('ideal, on geometry', (r) => r.ideal_speedup_hit ? fmt(r.ideal_speedup_hit) + '×' : '–', 'ideal-speedup-hit');
  both('ideal, 4×2 blocks', (r) => fmt(r.ideal_speedup_4x2_blocks) + '×', 'block-speedup');
  both('measured speedup, one warm run', (r) => `${fmt(r.explore.measured_speedup)}× (${fmt(r.explore.frame_ms)} vs ${fmt(r.explore.full_ms)} ms)`, 'measured-speedup');
  both('RMS vs full', (r) => r.error_vs_full ? fmt(r.error_vs_full.rms) : '–', 'rms');
  both('SSIM vs full', (r) => r.error_vs_full ? fmt(r.error_vs_full.ssim, 4) : '–', 'ssim');
  for (const lv of cpu.levels) {
    const shaded = (r) => (r.levels[lv.level].enabled && r.levels[lv.level].shaded ? String(r.levels[lv.level].shaded_pixels) : 'off');
    both(`shaded L${lv.level} (1/${lv.scale})`, shaded, 'shaded-L' + lv.level);
  }
  both('shaded in all', (r) => `${r.shaded_pixels_total} of ${r.width * r.height}`, 'shaded-total');
  const body = $('#stats tbody');
  body.replaceChildren();
  const head = document.createElement('tr');
  for (const t of ['', 'oracle', gpu ? 'port' : '']) {
    const th = document.createElement('th');
    th.textContent = t;
    head.appendChild(th);
  }
  body.appendChild(head);
  for (const [label, a, b, id] of rows) {
    const tr = document.createElement('tr');
    const th = document.createElement('th');
    th.textContent = label;
    const ta = document.createElement('td');
    ta.id = id;
    ta.textContent = a;
    tr.append(th, ta);
    if (b !== null) {
      const tb = document.createElement('td');
      tb.id = id + '-port';
      tb.textContent = b;
      if (b !== a) tb.classList.add('differs');
      tr.appendChild(tb);
    }
    body.appendChild(tr);
  }
  $('#stats-note').textContent = 'Measured: this frame\'s total against the full-resolution frame\'s, one run each on ' +
    'this machine, warm, the stages kept for the page; `mrr bench` gives careful figures.';
  if (gpu && gpu.renderer) $('#port-name').textContent = gpu.renderer.split('(')[0].trim();
}

// ---------------------------------------------------------------------------------------------
// Layers.

function stepOf(name) {
  const head = name.split('.')[0];
  const part = state.info.parts.find((p) => p.name === head);
  return part ? part.step : 7;  // difference, flip: against the full-resolution frame
}
const stepNames = {1: '1 · G-buffer and shadow map', 2: '2 · edges', 3: '3 · masks and stencils', 4: '4 · sub-images',
  5: '5 · upsample and blend', 6: '6 · shading', 7: 'against full resolution'};

function fillLayers(layers) {
  const same = layers.length === state.layers.length && layers.every((l, i) => l === state.layers[i]);
  state.layers = layers;
  if (!layers.includes(state.layer)) state.layer = layers.includes('final') ? 'final' : layers[0];
  if (same) return;
  const sel = $('#layer');
  sel.replaceChildren();
  let group = null, step = 0;
  for (const name of layers) {
    if (stepOf(name) !== step || !group) {
      step = stepOf(name);
      group = document.createElement('optgroup');
      group.label = stepNames[step] || 'step ' + step;
      sel.appendChild(group);
    }
    const o = document.createElement('option');
    o.value = o.textContent = name;
    group.appendChild(o);
  }
  sel.value = state.layer;
}

function legend(el, meta) {
  el.replaceChildren();
  const bar = document.createElement('div');
  bar.className = 'bar';
  const labels = document.createElement('div');
  labels.className = 'labels';
  const span = (t) => { const s = document.createElement('span'); s.textContent = t; return s; };
  if (meta.kind === 'binary') {
    bar.style.background = 'linear-gradient(to right, #000 50%, #fff 50%)';
    labels.append(span('0'), span(`${meta.ones} ones`), span('1'));
  } else if (meta.kind === 'effect') {
    bar.style.background = 'linear-gradient(to right, #000, #fff)';
    labels.append(span('0'), span('1'));
  } else if (meta.kind === 'levels') {
    bar.style.background = 'linear-gradient(to right, ' + meta.swatches.map((c, i) => `${c} ${i * 25}%, ${c} ${(i + 1) * 25}%`).join(', ') + ')';
    const names = meta.name === 'tilerates' ? ['1×1', '2×2', '4×4', ''] : ['L0 full', 'L1 ½', 'L2 ¼', 'L3 ⅛'];
    labels.append(...names.map(span));
    labels.classList.add('four');
  } else if (meta.kind === 'reason') {  // SPEC §12.3: one swatch per reason
    const n = meta.swatches.length;
    bar.style.background = 'linear-gradient(to right, ' + meta.swatches.map((c, i) => `${c} ${(i * 100) / n}%, ${c} ${((i + 1) * 100) / n}%`).join(', ') + ')';
    labels.append(...meta.names.map(span));
    labels.classList.add('four');
  } else if (meta.kind === 'colour') {
    bar.style.display = 'none';
  } else {
    bar.style.background = meta.ramp;
    labels.append(span(fmt(meta.lo, 4)), span(fmt(meta.hi, 4)));
  }
  const cap = document.createElement('p');
  cap.textContent = meta.caption + (meta.kind === 'difference' ? `; ${meta.differing_pixels} pixel(s) differ` : '');
  el.append(bar, labels, cap);
}

async function showLayer(seq = state.seq) {
  const report = state.reports.cpu;
  if (!report) return;
  const name = state.layer;
  $('#layer').value = name;
  $('#gain-label').hidden = name !== 'difference';
  const gain = $('#gain').value || '10';
  const q = query({gain});
  const paths = state.port ? ['cpu', 'gpu', 'both'] : ['cpu'];
  $('#panel-gpu').classList.toggle('unavailable', !state.port);
  $('#panel-both').classList.toggle('unavailable', !state.port);
  busy(+1);
  try {
    const metas = await Promise.all(paths.map((p) => api(`/api/stage/${name}.json?${q}&path=${p}`)));
    if (seq !== state.seq) return;
    $('#layer-what').textContent = metas[0].what;
    const W = report.width, H = report.height;
    // three panels side by side where the window allows, each at most 3 screen pixels a pixel
    const room = Math.max(240, ($('#stage').clientWidth - 2 * 14) / (paths.length > 1 ? 3 : 1) - 36);
    state.zoom = Math.min(3, room / W);
    const loads = [];
    paths.forEach((p, i) => {
      const meta = metas[i];
      const panel = $('#panel-' + p);
      const view = $('.view', panel), img = $('img', panel);
      view.style.width = W * state.zoom + 'px';
      view.style.height = H * state.zoom + 'px';
      const scale = meta.scale > 0 ? meta.scale : H / meta.height;  // the shadow map: fitted to the height
      img.style.width = meta.width * scale * state.zoom + 'px';
      img.style.height = meta.height * scale * state.zoom + 'px';
      loads.push(new Promise((resolve) => {
        img.onload = img.onerror = resolve;
        img.src = `/api/stage/${name}.png?${q}&path=${p}`;
      }));
      legend($('.legend', panel), meta);
      $('.legend', panel).style.width = W * state.zoom + 'px';
      panel.dataset.scale = meta.scale;
    });
    await Promise.all(loads);
    drawFootprint();
  } finally {
    busy(-1);
  }
}

function selectLayer(name) {
  state.layer = name;
  showLayer().catch((e) => say(e.message, true));
}

// ---------------------------------------------------------------------------------------------
// Hover and click.

function pixelOf(ev, view) {
  const r = view.getBoundingClientRect();
  const rep = state.reports.cpu;
  const x = Math.floor((ev.clientX - r.left) / state.zoom), y = Math.floor((ev.clientY - r.top) / state.zoom);
  if (!rep || x < 0 || y < 0 || x >= rep.width || y >= rep.height) return null;
  return [x, y];
}

let hoverTimer = null, hoverSeq = 0;
function hover(ev) {
  const view = ev.currentTarget;
  const px = pixelOf(ev, view);
  clearTimeout(hoverTimer);
  if (!px) return;
  const path = view.closest('.panel').dataset.path;
  hoverTimer = setTimeout(async () => {
    const mine = ++hoverSeq;
    const paths = path === 'both' ? ['cpu', 'gpu'] : [path];
    try {
      const vals = await Promise.all(paths.map((p) =>
        api(`/api/value?${query({gain: $('#gain').value || '10'})}&layer=${state.layer}&x=${px[0]}&y=${px[1]}&path=${p}`)));
      if (mine !== hoverSeq) return;
      const text = vals.map((v, i) => {
        const who = paths[i] === 'cpu' ? 'oracle' : 'port';
        if (!v.values) return `${who}: ${v.note}`;
        const list = Object.entries(v.values).map(([k, x]) => `${k} ${x === null ? '–' : fmt(x, 5)}`).join(', ');
        return `${who}: ${list || 'outside the layer'}`;
      }).join('  |  ');
      const g = vals[0].grid_pixel;
      $('#hover').textContent = `pixel ${px[0]},${px[1]}` + (g && (g[0] !== px[0] || g[1] !== px[1]) ? ` → ${state.layer.split('.')[1] || ''} pixel ${g[0]},${g[1]}` : '') +
        ` · ${state.layer} · ${text}`;
    } catch (e) { /* a hover that fails says nothing */ }
  }, 40);
}

function click(ev) {
  const px = pixelOf(ev, ev.currentTarget);
  if (!px) return;
  state.pixel = px;
  if ($('#gaze_click').checked) {  // foveation (SPEC §13): the eye looks here; render, then probe
    state.params.gaze = `${px[0]},${px[1]}`;
    render();
    return;
  }
  probe().catch((e) => say(e.message, true));
}

// ---------------------------------------------------------------------------------------------
// The probe of one pixel, and its footprint on the level's layer.

// A table row of text cells (td, or th for a header).
function tableRow(cells, tag = 'td') {
  const tr = document.createElement('tr');
  for (const c of cells) {
    const td = document.createElement(tag);
    td.textContent = c;
    tr.appendChild(td);
  }
  return tr;
}

function flatten(obj, prefix, rows) {
  if (obj === null || typeof obj !== 'object' || (Array.isArray(obj) && obj.every((x) => typeof x !== 'object'))) {
    rows.push([prefix, Array.isArray(obj) ? '(' + obj.map((x) => fmt(x, 7)).join(', ') + ')' : fmt(obj, 7)]);
    return;
  }
  for (const [k, v] of Object.entries(obj)) flatten(v, prefix ? `${prefix}.${k}` : k, rows);
}

async function probe() {
  if (!state.pixel) return;
  const [x, y] = state.pixel;
  let path = $('#probe-path').value;
  if (!state.port && path !== 'cpu') path = $('#probe-path').value = 'cpu';
  busy(+1);
  try {
    const j = await api(`/api/probe?${query()}&x=${x}&y=${y}&path=${path}`);
    $('#probe-pixel').textContent = `${x},${y}`;
    const head = $('#probe thead'), body = $('#probe tbody');
    head.replaceChildren();
    body.replaceChildren();
    if (path === 'both') {
      state.probe = j.oracle;
      head.appendChild(tableRow(['value', 'oracle', 'port', ''], 'th'));
      let first = true;
      let section = null;
      for (const r of j.rows) {
        if (r.section && r.section !== section) {  // one heading per pipeline step, with its shader
          section = r.section;
          const h = tableRow([section], 'th');
          h.firstChild.colSpan = 4;
          h.classList.add('probe-section');
          body.appendChild(h);
        }
        const tr = tableRow([r.key, r.oracle, r.port, r.differs ? (first ? '◀ first difference' : '≠') : '']);
        if (r.differs) {
          tr.classList.add('differs');
          if (first) { tr.classList.add('first'); tr.id = 'probe-first-difference'; first = false; }
        }
        body.appendChild(tr);
      }
      $('#probe-source').textContent = 'the oracle (cpu_ref) beside the port';
      $('#probe-verdict').textContent = j.first_difference ? `first difference: ${j.first_difference}` : 'the paths agree at every stage';
      $('#probe-verdict').className = j.first_difference ? 'bad' : 'good';
    } else {
      state.probe = j;
      head.appendChild(tableRow(['stage.value', path === 'cpu' ? 'oracle' : 'port'], 'th'));
      const rows = [];
      flatten(j, '', rows);
      for (const r of rows) body.appendChild(tableRow(r));
      $('#probe-source').textContent = path === 'cpu' ? 'the oracle (cpu_ref)' : 'the port (' + ($('#port-name').textContent || 'GL') + ')';
      $('#probe-verdict').textContent = '';
    }
    $('#probe-tolerance').textContent = `Numbers differ when |Δ| > ${state.info.probe_relative_difference} · max(1, |a|, |b|) ` +
      '(common/tolerance.h); everything else must be equal. `mrr probe --path both` prints the same table.';
    showWhy(path === 'both' ? j.oracle : j, path === 'both' ? j.port : null);
    $('#probe-section').dataset.pixel = `${x},${y}`;
    $('#probe-section').dataset.path = path;
    drawFootprint();
  } finally {
    busy(-1);
  }
  if ($('#probe-noise').checked) await noiseProbe();
  else $('#noise-section').hidden = true;
}

// The probed pixel's stochastic stages against the oracle's independent seeds (GET
// /api/noise: the same numbers as `mrr probe --path both --noise-aware`). The first request for a
// frame renders the seeds (progress in the bar); later pixels of the same frame read its cache.
async function noiseProbe() {
  const section = $('#noise-section');
  section.hidden = false;
  section.dataset.pixel = '';
  if (!state.pixel) return;
  const [x, y] = state.pixel;
  const head = $('#noise thead'), body = $('#noise tbody');
  head.replaceChildren();
  body.replaceChildren();
  const effect = state.params.effect || (state.info.defaults || {}).effect;
  if (effect === 'ssm') {
    $('#noise-note').textContent = 'ssm has no stochastic stage (its PCF grid is fixed): every value is judged exactly.';
    $('#noise-verdict').textContent = '';
    section.dataset.pixel = `${x},${y}`;
    return;
  }
  $('#noise-note').textContent = 'rendering the oracle with 16 independent seeds…';
  const path = $('#probe-path').value;
  busy(+1);
  let j;
  try {
    j = await api(`/api/noise?${query()}&x=${x}&y=${y}&path=${path}`);
  } catch (e) {
    $('#noise-note').textContent = 'noise-aware: ' + e.message;
    section.dataset.pixel = `${x},${y}`;
    throw e;
  } finally {
    busy(-1);
  }
  const last = j.first_seed + j.seeds - 1;
  $('#noise-note').textContent =
    `${j.subject} at pixel ${x},${y} against the oracle's ${j.seeds} frames with independent seeds ` +
    `(--seed ${j.first_seed}…${last}, ${j.samples} samples a pixel${j.reference_cached ? ', cached' : `, rendered in ${fmt(j.reference_seconds)} s`}). ` +
    'mean: the seeds\' mean here ± its 95% t interval; sd: one draw\'s spread; accepted: where compare --noise-aware accepts ' +
    'one draw (Welch\'s t at the stage\'s Šidák level: 1% false alarms over its pixels); t: the value\'s distance from the mean in sd.';
  head.appendChild(tableRow(['stage', 'pixel', j.path === 'gpu' ? 'port' : 'value', 'mean ± 95%', 'sd', 'accepted (Šidák level, px)', 't', 'where it falls'], 'th'));
  const outside = [];
  for (const s of j.stages) {
    const label = `${s.stage} (${s.shader})`;
    if (!s.shaded) {
      const tr = tableRow([label, s.pixel.join(','), '–', '', '', '', '', s.level >= 0 ? `not shaded here: level ${s.level}'s stencil leaves it to another level` : 'the background: no estimate']);
      tr.classList.add('unshaded');
      body.appendChild(tr);
      continue;
    }
    const c = s.channels[s.farthest_channel];
    const where = c.inside ? `inside (${c.half_widths.toFixed(2)} of the half-width from the mean)`
      : `OUTSIDE (${c.half_widths === null ? '∞' : fmt(c.half_widths)} half-widths ${c.value < c.mean ? 'below' : 'above'} the mean)`;
    const tr = tableRow([label, s.pixel.join(','), fmt(c.value, 4), `${fmt(c.mean, 4)} ± ${fmt((c.mean_interval_95[1] - c.mean_interval_95[0]) / 2, 2)}`,
      fmt(c.sd), `[${fmt(c.accepted[0], 4)}, ${fmt(c.accepted[1], 4)}] (${s.sidak_level.toExponential(1)}, ${s.stage_pixels})`,
      (c.t >= 0 ? '+' : '') + fmt(c.t), where + (s.channels.length > 1 ? ` [channel ${s.farthest_channel}, the farthest]` : '')]);
    tr.dataset.stage = s.stage;
    if (!c.inside) { tr.classList.add('outside'); outside.push(s.stage); }
    body.appendChild(tr);
  }
  $('#noise-verdict').textContent = outside.length
    ? `OUTSIDE the accepted interval at ${outside.join(', ')}: compare --noise-aware rejects this pixel there`
    : 'inside every accepted interval: as far as this pixel shows, a draw of the oracle\'s estimator ' +
      '(a shift of a few per cent shows in compare --noise-aware\'s bias over the frame, not at one pixel)';
  $('#noise-verdict').className = outside.length ? 'bad' : 'good';
  section.dataset.pixel = `${x},${y}`;
}

// SPEC §12.3: why each level covers the clicked pixel (mrr, mrr-effect), one line a level; with
// --path both, the port's reason beside the oracle's where they differ.
const WHY_TEXT = {
  coarsest: 'the coarsest level covers every pixel',
  fallback: 'the never-slower rule fell back to full',
  geometry: 'an edge (its block, or within the blur of one)',
  effect: "the effect's footprint: within reach of an edge, out of the edges' blur",
  marks: 'the a-posteriori marks: the coarser result varies by more than τ',
  closure: 'a finer level shades inside this pixel',
  limit: 'not covered: the level limit (foveation, motion) clears it',
  none: 'not covered: no edge, reach or mark within the blur',
};
function showWhy(probe, port) {
  const list = $('#probe-why');
  list.replaceChildren();
  if (!probe || !probe.levels) return;
  probe.levels.forEach((lv, l) => {
    if (!lv.why) return;
    const w = lv.why;
    let text = `level ${l}: ${w.reason}: ${WHY_TEXT[w.reason] || ''}`;
    if (w.reached_from) text += ` (edge pixel ${w.reached_from.join(',')}, reach ${w.reached_from_reach})`;
    if (w.mark_parent) text += ` (level-${w.mark_parent[0]} parent range ${fmt(w.mark_range, 3)}, τ ${w.tau})`;
    if (w.closure_from !== undefined) text += ` (level ${w.closure_from})`;
    const pw = port && port.levels && port.levels[l] && port.levels[l].why;
    if (pw && pw.reason !== w.reason) text += ` — the port: ${pw.reason}`;
    const li = document.createElement('li');
    li.textContent = text;
    li.dataset.reason = w.reason;
    list.appendChild(li);
  });
}

function drawFootprint() {
  const rep = state.reports.cpu;
  if (!rep) return;
  const m = state.layer.match(/\.L(\d)/);
  const level = m ? +m[1] : -1;
  const blendLayer = /^(upsample|blendalpha|composite)\./.test(state.layer);
  for (const panel of $$('.panel')) {
    const svg = $('svg', panel);
    svg.setAttribute('viewBox', `0 0 ${rep.width} ${rep.height}`);
    svg.style.width = rep.width * state.zoom + 'px';
    svg.style.height = rep.height * state.zoom + 'px';
    svg.replaceChildren();
    if (!state.pixel || +panel.dataset.scale === 0) continue;
    const ns = 'http://www.w3.org/2000/svg';
    const rect = (x, y, w, h, cls) => {
      const r = document.createElementNS(ns, 'rect');
      Object.entries({x, y, width: w, height: h}).forEach(([k, v]) => r.setAttribute(k, v));
      r.setAttribute('class', cls);
      svg.appendChild(r);
    };
    const [px, py] = state.pixel;
    const lv = state.probe && state.probe.levels ? state.probe.levels[level] : null;
    if (lv && lv.level_pixel && !blendLayer) {
      const s = lv.scale;
      rect(lv.level_pixel[0] * s, lv.level_pixel[1] * s, s, s, 'footprint');
    } else if (lv && lv.taps && blendLayer) {
      const s = lv.scale;
      for (const t of lv.taps) rect(t.q[0] * s, t.q[1] * s, s, s, t.S ? 'tap' : 'tap unshaded');
    }
    rect(px, py, 1, 1, 'pixel');
    const ring = document.createElementNS(ns, 'circle');
    ring.setAttribute('cx', px + 0.5);
    ring.setAttribute('cy', py + 0.5);
    ring.setAttribute('r', 6 / state.zoom + 2);
    ring.setAttribute('class', 'ring');
    svg.appendChild(ring);
  }
}

// ---------------------------------------------------------------------------------------------
// Teach mode: the stages in order on this frame, with docs/method.md's text.

let teachIndex = 0;
function teachSteps() {
  return state.info.teach
    .map((s) => ({...s, layer: state.layers.find((l) => l === s.part) || state.layers.find((l) => l.startsWith(s.part + '.'))}))
    .filter((s) => s.layer);
}

function inlineMarkdown(text) {  // `code`, **bold**, [text](link) → text; everything else as text
  const frag = document.createDocumentFragment();
  const re = /(`[^`]+`|\*\*[^*]+\*\*|\[[^\]]+\]\([^)]+\))/g;
  let last = 0;
  for (const m of text.matchAll(re)) {
    frag.append(text.slice(last, m.index));
    const t = m[0];
    let el;
    if (t[0] === '`') { el = document.createElement('code'); el.textContent = t.slice(1, -1); }
    else if (t[0] === '*') { el = document.createElement('strong'); el.textContent = t.slice(2, -2); }
    else { el = document.createElement('em'); el.textContent = t.slice(1, t.indexOf(']')); }
    frag.append(el);
    last = m.index + t.length;
  }
  frag.append(text.slice(last));
  return frag;
}

function showTeach() {
  const steps = teachSteps();
  if (!steps.length) return;
  teachIndex = Math.max(0, Math.min(steps.length - 1, teachIndex));
  const s = steps[teachIndex];
  $('#teach-panel').hidden = false;
  const title = $('#teach-title');
  title.replaceChildren(`${teachIndex + 1}/${steps.length} · ${s.part} — `, inlineMarkdown(s.section));
  $('#teach-what').textContent = s.what;
  const text = $('#teach-text');
  text.replaceChildren();
  const p = document.createElement('p');
  p.appendChild(inlineMarkdown(s.text));
  text.appendChild(p);
  $('#teach-panel').dataset.part = s.part;
  selectLayer(s.layer);
}

// ---------------------------------------------------------------------------------------------
// Start.

async function start() {
  busy(+1);
  try {
    state.info = await api('/api/info');
  } finally {
    busy(-1);
  }
  const info = state.info;
  state.port = info.port.available;
  if (!state.port) {
    $('#probe-path').value = 'cpu';
    $$('#probe-path option').forEach((o) => { o.disabled = o.value !== 'cpu'; });
    $('#port-name').textContent = 'unavailable: ' + info.port.status;
  }
  document.body.dataset.port = state.port ? 'available' : 'unavailable';
  const scene = $('#scene');
  for (const s of info.scenes) {
    const o = document.createElement('option');
    o.value = o.textContent = s;
    scene.appendChild(o);
  }
  // The methods, from the server's method table (common/methods.h): one option each.
  for (const m of info.methods) {
    const o = document.createElement('option');
    o.value = m.name;
    o.textContent = m.label;
    o.title = m.help;
    $('#method').appendChild(o);
  }
  // Each knob's help, unit and range come from the frame-parameter table the server reads
  // (common/frame_params.h): one text for the command line's --help and the page.
  const rows = Object.fromEntries((info.params || []).map((r) => [r.key, r]));
  for (const el of $$('[data-param]')) {
    const row = rows[el.dataset.param];
    if (row) el.title = `${row.option}: ${row.help}`;
    else console.warn(`knob ${el.dataset.param}: not a frame parameter the server accepts`);
  }
  const d = info.defaults;
  scene.value = d.scene;
  $('#effect').value = d.effect;
  const method = info.methods.find((m) => m.name === d.method) || info.methods[0];  // an alias: its row's first
  $('#method').value = method.name;
  if (![...$('#size').options].some((o) => o.value === d.size)) {
    const o = document.createElement('option');
    o.textContent = d.size;
    $('#size').appendChild(o);
  }
  $('#size').value = d.size;
  if (d.samples) $('#samples').value = d.samples;
  $('#tau_n').value = d.tau_n;
  $('#tau_z').value = d.tau_z;
  $('#never_slower').checked = d.never_slower === 'on';
  readControls();
  if (!d.samples) delete state.params.samples;

  for (const el of $$('#controls select, #controls input')) el.addEventListener('change', changed);
  $('#layer').addEventListener('change', (e) => selectLayer(e.target.value));
  $('#layer-prev').addEventListener('click', () => selectLayer(state.layers[Math.max(0, state.layers.indexOf(state.layer) - 1)]));
  $('#layer-next').addEventListener('click', () => selectLayer(state.layers[Math.min(state.layers.length - 1, state.layers.indexOf(state.layer) + 1)]));
  $('#gain').addEventListener('change', () => showLayer());
  for (const v of $$('.view')) {
    v.addEventListener('mousemove', hover);
    v.addEventListener('click', click);
  }
  $('#probe-path').addEventListener('change', () => probe().catch((e) => say(e.message, true)));
  $('#probe-noise').addEventListener('change', () => probe().catch((e) => say(e.message, true)));
  for (const b of $$('[data-orbit]')) {
    const [yaw, pitch] = b.dataset.orbit.split(',').map(Number);
    b.addEventListener('click', () => moveCamera(yaw, pitch, 1));
  }
  for (const b of $$('[data-dolly]')) b.addEventListener('click', () => moveCamera(0, 0, Number(b.dataset.dolly)));
  $('#camera-reset').addEventListener('click', () => { clearCamera(); render(); });
  $('#teach').addEventListener('click', () => { teachIndex = 0; showTeach(); });
  $('#teach-prev').addEventListener('click', () => { teachIndex--; showTeach(); });
  $('#teach-next').addEventListener('click', () => { teachIndex++; showTeach(); });
  $('#teach-close').addEventListener('click', () => { $('#teach-panel').hidden = true; });
  await render();
}

start().catch((e) => say('cannot start: ' + e.message, true));
