// The report's 3D view (docs/visualization.md, "The report's 3D view"): the final mesh, each
// robot's path, the viewpoints, the ISEs still inspectable and C_rem, with orbit controls,
// a legend and a toggle per layer. Bundled by esbuild into one classic script that
// `scancrew report` inlines into report.html (report/scene_view.hpp), so the page works
// offline from file://. The scene is the JSON of <script id="scancrew-scene">; its format is
// written in report/scene_view.hpp. World frame: x, y on the ground, z up, metres.
//
// State for the page's test (web/tests/report_page.mjs): document.body.dataset.viewer is
// "ready" after the first frame, "error: ..." when the view could not be built.

import * as THREE from 'three';
import { OrbitControls } from 'three/examples/jsm/controls/OrbitControls.js';

const BACKGROUND = 0xf4f5f7;

function decode(base64, Type) {
  const bytes = Uint8Array.from(atob(base64), (c) => c.charCodeAt(0));
  return new Type(bytes.buffer, 0, bytes.byteLength / Type.BYTES_PER_ELEMENT);
}

function robotColour(scene, id) {
  const r = scene.robots.find((x) => x.id === id);
  return new THREE.Color(r ? r.colour : '#888888');
}

// The mesh: positions quantised to 16 bits over its bounding box; coloured by the robot
// whose patches made each part (owner), else grey by height.
function buildMesh(scene) {
  const m = scene.mesh;
  const q = decode(m.positions, Uint16Array);
  const indices = decode(m.indices, Uint32Array);
  const owners = m.owners ? decode(m.owners, Uint8Array) : null;
  const n = q.length / 3;
  const positions = new Float32Array(3 * n);
  for (let i = 0; i < n; ++i)
    for (let k = 0; k < 3; ++k)
      positions[3 * i + k] = m.origin[k] + (q[3 * i + k] / 65535) * m.extent[k];
  const colours = new Float32Array(3 * n);
  const grey = new THREE.Color();
  for (let i = 0; i < n; ++i) {
    const h = m.extent[2] > 0 ? q[3 * i + 2] / 65535 : 0;
    let c = grey.setScalar(0.82 - 0.45 * h);
    if (owners && owners[i] > 0) c = robotColour(scene, owners[i]).lerp(new THREE.Color(1, 1, 1), 0.35);
    colours.set([c.r, c.g, c.b], 3 * i);
  }
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute('position', new THREE.BufferAttribute(positions, 3));
  geometry.setAttribute('color', new THREE.BufferAttribute(colours, 3));
  geometry.setIndex(new THREE.BufferAttribute(indices, 1));
  geometry.computeVertexNormals();
  const material = new THREE.MeshLambertMaterial({ vertexColors: true, side: THREE.FrontSide });
  return new THREE.Mesh(geometry, material);
}

// A robot's path, lifted a little above the floor, with a sphere at its start and a box at
// its end (as the top view's circle and square).
function buildPath(scene, path, marker) {
  const group = new THREE.Group();
  const colour = robotColour(scene, path.robot);
  const p = path.points;
  if (p.length < 3) return group;
  const lift = 0.05;
  const vertices = new Float32Array(p.length);
  for (let i = 0; i < p.length; i += 3) vertices.set([p[i], p[i + 1], p[i + 2] + lift], i);
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute('position', new THREE.BufferAttribute(vertices, 3));
  group.add(new THREE.Line(geometry, new THREE.LineBasicMaterial({ color: colour })));
  const material = new THREE.MeshBasicMaterial({ color: colour });
  const start = new THREE.Mesh(new THREE.SphereGeometry(marker, 16, 12), material);
  start.position.set(p[0], p[1], p[2] + lift);
  const end = new THREE.Mesh(new THREE.BoxGeometry(1.6 * marker, 1.6 * marker, 1.6 * marker), material);
  end.position.set(p[p.length - 3], p[p.length - 2], p[p.length - 1] + lift);
  group.add(start, end);
  return group;
}

function buildPoints(flat, colour, size) {
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute('position', new THREE.BufferAttribute(new Float32Array(flat), 3));
  const material = new THREE.PointsMaterial({ color: colour, size, sizeAttenuation: true });
  return new THREE.Points(geometry, material);
}

function legendRow(legend, label, swatch, object, note) {
  const row = document.createElement('label');
  row.className = 'v3d-row';
  const box = document.createElement('input');
  box.type = 'checkbox';
  box.checked = true;
  box.disabled = !object;
  box.addEventListener('change', () => {
    object.visible = box.checked;
  });
  const sw = document.createElement('span');
  sw.className = 'sw';
  sw.style.background = swatch;
  row.append(box, sw, document.createTextNode(label));
  if (note) {
    const small = document.createElement('span');
    small.className = 'small';
    small.textContent = ' ' + note;
    row.append(small);
  }
  legend.append(row);
}

function frameCamera(camera, controls, box) {
  const centre = box.getCenter(new THREE.Vector3());
  const size = box.getSize(new THREE.Vector3());
  const radius = Math.max(size.length() / 2, 1);
  camera.position.set(centre.x - 0.9 * radius, centre.y - 1.3 * radius, centre.z + 1.1 * radius);
  camera.near = radius / 100;
  camera.far = radius * 20;
  camera.updateProjectionMatrix();
  controls.target.copy(centre);
  controls.update();
}

function buildLayers(scene, world, legend) {
  const mesh = scene.mesh && scene.mesh.triangles > 0 ? buildMesh(scene) : null;
  if (mesh) world.add(mesh);
  const meshNote = scene.mesh && scene.mesh.note ? scene.mesh.note : '';
  legendRow(legend, scene.mesh && scene.mesh.owners ? 'mesh (tinted by the robot whose patches made it)'
    : 'mesh (grey by height)', '#b8b8b8', mesh, meshNote);
  // start and end markers: 15 cm, larger in large scenes so that they still show
  const extent = scene.mesh && scene.mesh.extent ? scene.mesh.extent : [0, 0, 0];
  const marker = Math.min(2, Math.max(0.15, Math.hypot(...extent) / 150));
  for (const path of scene.paths) {
    const g = buildPath(scene, path, marker);
    world.add(g);
    const r = scene.robots.find((x) => x.id === path.robot);
    legendRow(legend, `robot ${r ? r.name : path.robot}: path (sphere: start, box: end)`,
      robotColour(scene, path.robot).getStyle(), g);
  }
  const pointSize = scene.point_size_m || 0.2;
  const layers = [
    ['viewpoints', 'viewpoints of the last plan', '#2850e6', 1.0],
    ['inspectable', 'ISEs still inspectable (open)', '#28c828', 1.0],
    ['c_rem', 'C_rem: ISEs no robot can inspect (left open)', '#dc2828', 1.2],
  ];
  for (const [key, label, colour, scale] of layers) {
    const flat = scene.ises[key] || [];
    const object = flat.length ? buildPoints(flat, colour, pointSize * scale) : null;
    if (object) world.add(object);
    legendRow(legend, `${label}: ${flat.length / 3}`, colour, object);
  }
  return mesh;
}

function main() {
  const container = document.getElementById('scancrew-3d');
  const data = document.getElementById('scancrew-scene');
  if (!container || !data) return;
  const scene = JSON.parse(data.textContent);
  const legend = document.getElementById('scancrew-3d-legend');

  const renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
  renderer.setPixelRatio(window.devicePixelRatio || 1);
  const width = container.clientWidth || 800;
  const height = Math.round(width * 0.6);
  renderer.setSize(width, height);
  container.append(renderer.domElement);

  const world = new THREE.Scene();
  world.background = new THREE.Color(BACKGROUND);
  world.add(new THREE.HemisphereLight(0xffffff, 0x8a8a8a, 2.2));
  const sun = new THREE.DirectionalLight(0xffffff, 1.6);
  sun.position.set(0.4, -0.6, 1.0);
  world.add(sun);
  const camera = new THREE.PerspectiveCamera(45, width / height, 0.05, 1000);
  camera.up.set(0, 0, 1);
  const controls = new OrbitControls(camera, renderer.domElement);
  controls.enableDamping = false;

  buildLayers(scene, world, legend);
  const box = new THREE.Box3().setFromObject(world);
  if (box.isEmpty()) box.set(new THREE.Vector3(-5, -5, 0), new THREE.Vector3(5, 5, 2));
  const grid = new THREE.GridHelper(Math.ceil(box.getSize(new THREE.Vector3()).length()), 20, 0xc8c8c8, 0xdedede);
  grid.rotation.x = Math.PI / 2;
  grid.position.set(box.getCenter(new THREE.Vector3()).x, box.getCenter(new THREE.Vector3()).y, box.min.z - 0.01);
  world.add(grid);
  frameCamera(camera, controls, box);

  const render = () => renderer.render(world, camera);
  controls.addEventListener('change', render);
  const reset = document.getElementById('scancrew-3d-reset');
  if (reset) reset.addEventListener('click', () => { frameCamera(camera, controls, box); render(); });
  if (legend) legend.addEventListener('change', render);
  window.addEventListener('resize', () => {
    const w = container.clientWidth || width;
    const h = Math.round(w * 0.6);
    renderer.setSize(w, h);
    camera.aspect = w / h;
    camera.updateProjectionMatrix();
    render();
  });
  render();
  document.body.dataset.viewer = 'ready';
}

try {
  main();
} catch (e) {
  document.body.dataset.viewer = 'error: ' + e;
  const container = document.getElementById('scancrew-3d');
  if (container) container.textContent = '3D view unavailable: ' + e.message;
  throw e;
}
