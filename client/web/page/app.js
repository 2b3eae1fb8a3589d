// The ispars viewer: the scene list, then one scene's mesh, its roadmap growing batch by batch
// over a WebSocket from ispars-web, its build progress, and a tour on request.
import * as THREE from 'three';
import { OrbitControls } from './OrbitControls.js';

const $ = (id) => document.getElementById(id);
const params = new URLSearchParams(location.search);
const sceneName = params.get('scene');

// What the page has drawn, for people and for tests.
const viewer = { vertices: 0, edges: 0, generation: null, batches: 0, frames: 0, tour: null, mesh: false, errors: [],
                 tasks: [], task_pois: 0 };
window.viewer = viewer;

async function listScenes() {
  try {
    const r = await fetch('/api/scenes');
    const body = await r.json();
    const ul = $('scenes');
    ul.innerHTML = '';
    if (!r.ok) throw new Error(body.error || r.statusText);
    if (body.scenes.length === 0) ul.innerHTML = '<li>no scenes on any daemon</li>';
    for (const s of body.scenes) {
      const li = document.createElement('li');
      const a = document.createElement('a');
      a.href = '?scene=' + encodeURIComponent(s.name);
      a.textContent = s.name;
      li.append(a, ` (${s.server_id}${s.loaded ? ', loaded' : ''}${s.has_roadmap ? ', roadmap' : ''})`);
      ul.append(li);
    }
  } catch (e) {
    $('scenes').innerHTML = '';
    showError('scene list: ' + e.message);
  }
}

function showError(message) {
  viewer.errors.push(message);
  $('error').textContent = message;
}

// --- drawing ---------------------------------------------------------------------------------
const view = $('view');
const renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
renderer.setPixelRatio(window.devicePixelRatio);
view.append(renderer.domElement);
const scene3 = new THREE.Scene();
scene3.background = new THREE.Color(0xe8eef6);
const camera = new THREE.PerspectiveCamera(45, 1, 0.1, 5000);
camera.up.set(0, 0, 1);
camera.position.set(40, -55, 35);
const controls = new OrbitControls(camera, renderer.domElement);
scene3.add(new THREE.HemisphereLight(0xffffff, 0x667788, 1.6));
const sun = new THREE.DirectionalLight(0xffffff, 1.4);
sun.position.set(0.6, -0.8, 1.5);
scene3.add(sun);

// Growable buffers: vertices as points, edges as segments (positions copied per end).
class Growing {
  constructor(perItem, make) { this.perItem = perItem; this.make = make; this.count = 0; this.alloc(1024); }
  alloc(capacity) {
    const old = this.array;
    this.capacity = capacity;
    this.array = new Float32Array(capacity * this.perItem);
    if (old) this.array.set(old.subarray(0, this.count * this.perItem));
    if (this.object) scene3.remove(this.object);
    const g = new THREE.BufferGeometry();
    g.setAttribute('position', new THREE.BufferAttribute(this.array, 3));
    this.object = this.make(g);
    this.object.frustumCulled = false;
    scene3.add(this.object);
    this.update();
  }
  push(values) {
    const items = values.length / this.perItem;
    if (this.count + items > this.capacity) this.alloc(Math.max(this.capacity * 2, this.count + items));
    this.array.set(values, this.count * this.perItem);
    this.count += items;
    this.update();
  }
  clear() { this.count = 0; this.update(); }
  update() {
    const g = this.object.geometry;
    g.setDrawRange(0, this.count * this.perItem / 3);
    g.attributes.position.needsUpdate = true;
  }
}
const points = new Growing(3, (g) => new THREE.Points(g, new THREE.PointsMaterial({ color: 0x0d2673, size: 3, sizeAttenuation: false })));
const lines = new Growing(6, (g) => new THREE.LineSegments(g, new THREE.LineBasicMaterial({ color: 0x1f55d9, transparent: true, opacity: 0.55 })));
let positions = new Float32Array(0);  // every vertex's xyz, for edge ends
let tourLine = null;
let taskPoints = null;  // the chosen task's POIs
let framed = false;

function frame(box) {
  if (box.isEmpty()) return;
  const centre = box.getCenter(new THREE.Vector3());
  const radius = box.getSize(new THREE.Vector3()).length() / 2;
  const distance = radius / Math.sin(THREE.MathUtils.degToRad(camera.fov / 2));
  camera.position.copy(centre).add(new THREE.Vector3(0.55, -0.75, 0.42).normalize().multiplyScalar(distance));
  camera.near = distance / 1000;
  camera.far = distance * 10;
  camera.updateProjectionMatrix();
  controls.target.copy(centre);
  controls.update();
  framed = true;
}

function resize() {
  const w = view.clientWidth, h = view.clientHeight;
  renderer.setSize(w, h);
  camera.aspect = w / Math.max(h, 1);
  camera.updateProjectionMatrix();
}
window.addEventListener('resize', resize);
resize();
renderer.setAnimationLoop(() => {
  controls.update();
  renderer.render(scene3, camera);
  viewer.frames++;
});

async function loadMesh(name) {
  const r = await fetch('/api/mesh/' + encodeURIComponent(name));
  if (!r.ok) {
    $('mesh_note').textContent = (await r.text()).trim();
    return;
  }
  const data = await r.arrayBuffer();
  const head = new Uint32Array(data, 0, 2);
  const xyz = new Float32Array(data, 8, head[0] * 3);
  const index = new Uint32Array(data, 8 + head[0] * 12, head[1] * 3);
  const g = new THREE.BufferGeometry();
  g.setAttribute('position', new THREE.BufferAttribute(xyz, 3));
  g.setIndex(new THREE.BufferAttribute(index, 1));
  g.computeVertexNormals();
  const mesh = new THREE.Mesh(g, new THREE.MeshLambertMaterial({ color: 0xc9c2b8, side: THREE.DoubleSide, flatShading: true }));
  scene3.add(mesh);
  g.computeBoundingBox();
  frame(g.boundingBox.clone().expandByScalar(2));
  viewer.mesh = true;
}

// --- the stream ----------------------------------------------------------------------------
function onBatch(m) {
  if (m.first_vertex !== viewer.vertices) return showError(`batch out of order at vertex ${m.first_vertex}`);
  const needed = (viewer.vertices + m.positions.length / 3) * 3;
  if (positions.length < needed) {
    const grown = new Float32Array(Math.max(needed, positions.length * 2));
    grown.set(positions);
    positions = grown;
  }
  positions.set(m.positions, viewer.vertices * 3);
  points.push(m.positions);
  viewer.vertices += m.positions.length / 3;
  const ends = new Float32Array(m.edges.length * 3);
  for (let i = 0; i < m.edges.length; i++) ends.set(positions.subarray(m.edges[i] * 3, m.edges[i] * 3 + 3), i * 3);
  lines.push(ends);
  viewer.edges = m.edges_sent;
  viewer.batches++;
  $('vertices').textContent = viewer.vertices;
  $('edges').textContent = viewer.edges;
  $('note').textContent = m.note;
  if (!framed && viewer.vertices > 0) {
    const box = new THREE.Box3().setFromArray(positions.subarray(0, viewer.vertices * 3));
    frame(box);
  }
}

function onStatus(m) {
  $('owner').textContent = m.server_id;
  $('daemon_note').textContent = m.daemon_gone
      ? `daemon ${m.server_id} has left the DDS domain: showing its last roadmap until a daemon holds the scene`
      : '';
  $('state').textContent = m.state + (m.last_error ? ` (${m.last_error})` : '');
  $('samples').textContent = `${m.samples_done} of ${m.samples_target}`;
  $('progress').value = m.samples_target > 0 ? m.samples_done / m.samples_target : 1;
  $('daemon_vertices').textContent = m.vertices;
  $('daemon_edges').textContent = m.edges;
  $('pois').textContent = `${m.pois_covered} of ${m.poi_count}`;
  // A task added or removed (or the first status): ask for the task list again.
  if (!viewer.status || viewer.status.tasks !== m.tasks || viewer.status.poi_count !== m.poi_count) askTasks();
  viewer.status = m;
}

// The scene's inspection tasks: the choice of a task draws its POIs and aims the tour at them.
let askTasks = () => {};
function onTasks(m) {
  viewer.tasks = m.tasks;
  const select = $('task');
  const chosen = select.value;
  select.innerHTML = '<option value="">every POI</option>';
  for (const t of m.tasks) {
    const o = document.createElement('option');
    o.value = t.name;
    o.textContent = `${t.name} (${t.poi_count} POIs)`;
    select.append(o);
  }
  select.value = m.tasks.some((t) => t.name === chosen) ? chosen : '';
  showTask();
}

function showTask() {
  if (taskPoints) scene3.remove(taskPoints);
  taskPoints = null;
  viewer.task_pois = 0;
  const t = viewer.tasks.find((x) => x.name === $('task').value);
  $('task_info').textContent = t ? `task ${t.name}: ${t.poi_count} POIs (ids ${t.first_poi}..` +
      `${t.first_poi + t.poi_count - 1}), ${t.pois_covered_root} seen from the root's component` +
      (t.positions ? '' : `; not drawn: ${t.not_drawn}`) : '';
  if (t && !t.positions && t.not_drawn.startsWith('not yet')) setTimeout(askTasks, 1000);
  if (!t || !t.positions) return;
  const g = new THREE.BufferGeometry();
  g.setAttribute('position', new THREE.BufferAttribute(new Float32Array(t.positions), 3));
  taskPoints = new THREE.Points(g, new THREE.PointsMaterial({ color: 0x17a34a, size: 6, sizeAttenuation: false }));
  scene3.add(taskPoints);
  viewer.task_pois = t.positions.length / 3;
}
$('task').onchange = showTask;

function onTour(m) {
  if (tourLine) scene3.remove(tourLine);
  const g = new THREE.BufferGeometry().setFromPoints(m.positions.map((p) => new THREE.Vector3(p[0], p[1], p[2])));
  tourLine = new THREE.Line(g, new THREE.LineBasicMaterial({ color: 0xff8000 }));
  scene3.add(tourLine);
  viewer.tour = m;
  $('tour').textContent = `tour of ${m.cost.toFixed(1)} m (on the roadmap ${m.roadmap_cost.toFixed(1)} m) ` +
      `through ${m.positions.length} waypoints, ` +
      `${m.covered} of ${m.targets} POIs${m.task ? ` of task ${m.task}` : ''}${m.valid ? '' : ' (NOT valid)'}`;
  $('tour_button').disabled = false;
}

function connect(name) {
  // wss under https (behind a TLS proxy): a browser blocks ws:// from an https page.
  const scheme = location.protocol === 'https:' ? 'wss' : 'ws';
  const ws = new WebSocket(`${scheme}://${location.host}/ws?scene=${encodeURIComponent(name)}`);
  ws.onmessage = (event) => {
    const m = JSON.parse(event.data);
    if (m.type === 'status') onStatus(m);
    else if (m.type === 'reset') {
      $('error').textContent = '';  // the scene is followed now, whatever kept it from being so
      points.clear(); lines.clear();
      viewer.vertices = 0; viewer.edges = 0; viewer.generation = m.generation;
    } else if (m.type === 'batch') onBatch(m);
    else if (m.type === 'tour') onTour(m);
    else if (m.type === 'tasks') onTasks(m);
    else if (m.type === 'error') { showError(m.message); $('tour_button').disabled = false; }
  };
  ws.onopen = () => { $('error').textContent = ''; };
  askTasks = () => { if (ws.readyState === WebSocket.OPEN) ws.send(JSON.stringify({ type: 'tasks' })); };
  ws.onclose = () => {
    showError('disconnected from ispars-web; reconnecting in 2 s');
    setTimeout(() => connect(name), 2000);
  };
  $('tour_button').onclick = () => {
    $('tour_button').disabled = true;
    $('tour').textContent = 'searching...';
    const task = $('task').value;
    ws.send(JSON.stringify(task ? { type: 'tour', budget: 2, task } : { type: 'tour', budget: 2 }));
  };
}

listScenes();
if (sceneName) {
  $('current').hidden = false;
  $('scene').textContent = sceneName;
  document.title = `${sceneName} - ispars viewer`;
  loadMesh(sceneName).catch((e) => showError('mesh: ' + e.message));
  connect(sceneName);
}
