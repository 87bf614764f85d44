// The 3-D view of a planemap report (an ES module, inlined into the page by the report writer,
// report/src/html_report.cpp). It reads the JSON blob #report-data (world frame, z up, metres)
// and draws, with three.js: plane outlines coloured by object, map edges, trihedral corners,
// object centres and grasp axes, and the trajectories and paths. #view gets data-state="ready"
// once the first frame is drawn (the browser test waits for it), or "error" with a message.
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';

const BACKGROUND = 0xf4f4f0;  // the browser test counts pixels that differ from it
const STRUCTURE_COLOR = '#b8b8b0';  // floor, walls and planes of no object
const EDGE_COLOR = '#202020';
const CORNER_COLOR = '#d01010';

const view = document.getElementById('view');
const data = JSON.parse(document.getElementById('report-data').textContent);

// One toggle per layer in the legend (#legend), so a crowded view can be thinned out.
function addLayer(scene, name, color, objects) {
  const group = new THREE.Group();
  group.name = name;
  for (const o of objects) group.add(o);
  scene.add(group);
  const item = document.createElement('label');
  item.className = 'layer';
  item.dataset.layer = name;
  const box = document.createElement('input');
  box.type = 'checkbox';
  box.checked = true;
  box.addEventListener('change', () => { group.visible = box.checked; });
  const swatch = document.createElement('span');
  swatch.className = 'swatch';
  swatch.style.background = color;
  item.append(box, swatch, document.createTextNode(' ' + name));
  document.getElementById('legend').append(item);
  return group;
}

const vec = (p) => new THREE.Vector3(p[0], p[1], p[2]);

function lineOf(points, color, closed = false) {
  const geometry = new THREE.BufferGeometry().setFromPoints(points.map(vec));
  const material = new THREE.LineBasicMaterial({ color });
  return closed ? new THREE.LineLoop(geometry, material) : new THREE.Line(geometry, material);
}

function dotsOf(points, color, size) {
  const geometry = new THREE.BufferGeometry().setFromPoints(points.map(vec));
  return new THREE.Points(geometry, new THREE.PointsMaterial({ color, size, sizeAttenuation: false }));
}

// A convex outline as a filled fan of triangles, and its border.
function planeMeshes(plane, color, structure) {
  const n = plane.outline.length;
  if (n < 3) return [];
  const positions = plane.outline.flat();
  const index = [];
  for (let k = 1; k + 1 < n; ++k) index.push(0, k, k + 1);
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute('position', new THREE.Float32BufferAttribute(positions, 3));
  geometry.setIndex(index);
  geometry.computeVertexNormals();
  const material = new THREE.MeshLambertMaterial({
    color, side: THREE.DoubleSide, transparent: true, opacity: structure ? 0.35 : 0.8,
    depthWrite: !structure,
    // Coplanar outlines (a box top over the floor's hull) would flicker without an offset.
    polygonOffset: true, polygonOffsetFactor: 1, polygonOffsetUnits: 1,
  });
  const mesh = new THREE.Mesh(geometry, material);
  mesh.userData.planeId = plane.id;
  const border = lineOf(plane.outline, new THREE.Color(color).multiplyScalar(0.6), true);
  return [mesh, border];
}

function buildScene() {
  const scene = new THREE.Scene();
  scene.background = new THREE.Color(BACKGROUND);
  scene.add(new THREE.AmbientLight(0xffffff, 1.6));
  const sun = new THREE.DirectionalLight(0xffffff, 1.4);
  sun.position.set(2, -3, 5);
  scene.add(sun);

  const objectColor = new Map(data.objects.map((o) => [o.id, o.color]));
  const structure = [], objectPlanes = [];
  for (const p of data.planes) {
    const owned = p.object >= 0 && objectColor.has(p.object);
    (owned ? objectPlanes : structure).push(...planeMeshes(p, owned ? objectColor.get(p.object) : STRUCTURE_COLOR, !owned));
  }
  addLayer(scene, 'floor, walls, other planes', STRUCTURE_COLOR, structure);
  const faceColors = data.objects.length ? data.objects.map((o) => o.color) : [STRUCTURE_COLOR];
  addLayer(scene, 'object faces', `linear-gradient(90deg, ${faceColors.join(', ')}, ${faceColors[0]})`, objectPlanes);

  const edges = data.edges.map((e) => lineOf([e.start, e.end], EDGE_COLOR));
  addLayer(scene, 'edges', EDGE_COLOR, edges);
  addLayer(scene, 'trihedral corners', CORNER_COLOR, data.corners.length ? [dotsOf(data.corners, CORNER_COLOR, 9)] : []);

  const markers = [];
  for (const o of data.objects) {
    const centre = new THREE.Mesh(new THREE.SphereGeometry(0.025, 16, 12), new THREE.MeshLambertMaterial({ color: o.color }));
    centre.position.copy(vec(o.center));
    markers.push(centre);
    if (o.grasp_axis) {
      const length = 0.5 * Math.max(...o.dimensions) + 0.15;
      markers.push(new THREE.ArrowHelper(vec(o.grasp_axis), vec(o.center), length, o.color, 0.06, 0.035));
    }
  }
  addLayer(scene, 'object centres, grasp axes', '#444', markers);

  for (const s of data.series) {
    const shape = s.style === 'points' ? dotsOf(s.points, s.color, s.size) : lineOf(s.points, s.color);
    addLayer(scene, s.name, s.color, s.points.length ? [shape] : []);
  }
  return scene;
}

// A view from behind and above the start, looking at the middle of everything drawn.
function frame(camera, controls, scene) {
  const box = new THREE.Box3().setFromObject(scene);
  if (box.isEmpty()) box.set(new THREE.Vector3(-1, -1, 0), new THREE.Vector3(1, 1, 1));
  const centre = box.getCenter(new THREE.Vector3());
  const radius = Math.max(box.getSize(new THREE.Vector3()).length() / 2, 0.5);
  const distance = radius / Math.sin(THREE.MathUtils.degToRad(camera.fov / 2));
  camera.position.copy(centre).add(new THREE.Vector3(-0.55, -0.45, 0.7).normalize().multiplyScalar(distance * 0.6));
  camera.near = distance / 1000;
  camera.far = distance * 10;
  camera.updateProjectionMatrix();
  controls.target.copy(centre);
  controls.update();
}

function main() {
  const renderer = new THREE.WebGLRenderer({ antialias: true });
  renderer.setPixelRatio(window.devicePixelRatio);
  view.append(renderer.domElement);
  const camera = new THREE.PerspectiveCamera(45, 1, 0.01, 100);
  camera.up.set(0, 0, 1);  // the world's z is up
  const controls = new OrbitControls(camera, renderer.domElement);
  const scene = buildScene();
  const grid = new THREE.GridHelper(10, 20, 0xcccccc, 0xe0e0e0);
  grid.rotation.x = Math.PI / 2;  // GridHelper lies in x-z; the floor is x-y
  frame(camera, controls, scene);
  scene.add(grid);

  const render = () => renderer.render(scene, camera);
  const resize = () => {
    const width = view.clientWidth, height = view.clientHeight;
    renderer.setSize(width, height);
    camera.aspect = width / height;
    camera.updateProjectionMatrix();
    render();
  };
  controls.addEventListener('change', render);
  new ResizeObserver(resize).observe(view);
  resize();
  view.dataset.state = 'ready';
}

try {
  main();
} catch (e) {
  view.dataset.state = 'error';
  view.textContent = '3-D view unavailable: ' + e.message;
}
