// softface serve's page: the surface at rest from /surface.bin, sliders per
// moved segment, each change sent over a WebSocket; the binary answer is the
// surface's displacement, drawn with three.js and coloured by |u|.
// window.softface exposes the state to the headless-browser test.
import * as THREE from "three";
import { OrbitControls } from "three/addons/controls/OrbitControls.js";

const state = { ready: false, replans: 0, latencies: [], lastMax: 0, errors: [], pending: null,
                inFlight: null, nextId: 1 };
window.softface = state;

function readSurface(buffer) {
  const head = new Uint32Array(buffer, 0, 2);
  const n = head[0], m = head[1];
  const positions = new Float32Array(buffer, 8, 3 * n);
  const index = new Uint32Array(buffer, 8 + 12 * n, 3 * m);
  return { positions: positions.slice(), index: index.slice() };
}

function colourMap(t) {
  // Blue (0) through white to red (1): a diverging map read as "how far".
  t = Math.min(1, Math.max(0, t));
  return t < 0.5 ? [2 * t, 2 * t, 1] : [1, 2 - 2 * t, 2 - 2 * t];
}

// A file of the server, or the page says which one failed.
async function get(path) {
  const response = await fetch(path);
  if (!response.ok) {
    document.getElementById("error").textContent = `${path}: ${response.status} ${await response.text()}`;
    throw new Error(`${path}: ${response.status}`);
  }
  return response;
}
const scene = await (await get("/scene.json")).json();
const rest = readSurface(await (await get("/surface.bin")).arrayBuffer());
const post = scene.post_operative ? readSurface(await (await get("/postop.bin")).arrayBuffer()) : null;
// The points a plan can move: each answer holds their displacements only.
const movingBytes = await (await get("/moving.bin")).arrayBuffer();
const moving = new Uint32Array(movingBytes, 4, new Uint32Array(movingBytes, 0, 1)[0]);
const restDistance = post ? new Float32Array(await (await get("/rest_distance.bin")).arrayBuffer()) : null;
document.getElementById("surface-kind").textContent =
  `${scene.surface}: ${scene.points} points, ${scene.triangles} triangles`;
if (!post) {
  document.getElementById("post-choice").style.display = "none";
  document.getElementById("distance-choice").style.display = "none";
}

const view = document.getElementById("view");
// No multisampling: in software WebGL it costs more than the face's update.
const renderer = new THREE.WebGLRenderer({ antialias: false, preserveDrawingBuffer: true });
renderer.setPixelRatio(window.devicePixelRatio);
renderer.setSize(view.clientWidth, view.clientHeight);
view.prepend(renderer.domElement);
const world = new THREE.Scene();
world.background = new THREE.Color(0xffffff);
world.add(new THREE.HemisphereLight(0xffffff, 0x666666, 1.6));
const light = new THREE.DirectionalLight(0xffffff, 1.5);
world.add(light);

function meshOf(surface) {
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute("position", new THREE.BufferAttribute(surface.positions.slice(), 3));
  geometry.setIndex(new THREE.BufferAttribute(surface.index, 1));
  const colours = new Float32Array(surface.positions.length).fill(0.85);
  geometry.setAttribute("color", new THREE.BufferAttribute(colours, 3));
  geometry.computeVertexNormals();
  const material = new THREE.MeshLambertMaterial({ vertexColors: true, side: THREE.DoubleSide });
  return new THREE.Mesh(geometry, material);
}
const face = meshOf(rest);
// Its bounding sphere is the one at rest: the moved face must not be culled.
// (Its normals are too: the shading lags the motion, which recomputing them
// for 400k triangles on every re-plan would cost more than the rest.)
face.frustumCulled = false;
world.add(face);
const postMesh = post ? meshOf(post) : null;
if (postMesh) { postMesh.visible = false; world.add(postMesh); }

face.geometry.computeBoundingSphere();
const sphere = face.geometry.boundingSphere;
const camera = new THREE.PerspectiveCamera(35, view.clientWidth / view.clientHeight,
                                           sphere.radius / 100, sphere.radius * 20);
// The face looks along -y in the patients' frame: the camera in front (-y), z up.
camera.up.set(0, 0, 1);
// Far enough that the whole surface fits the 35 degree field of view.
const cameraDistance = 1.15 * sphere.radius / Math.tan((35 / 2) * Math.PI / 180);
camera.position.copy(sphere.center).add(new THREE.Vector3(0, -cameraDistance, 0.1 * cameraDistance));
const controls = new OrbitControls(camera, renderer.domElement);
controls.target.copy(sphere.center);
controls.update();
controls.addEventListener("change", () => requestAnimationFrame(draw));
window.addEventListener("resize", () => {
  renderer.setSize(view.clientWidth, view.clientHeight);
  camera.aspect = view.clientWidth / view.clientHeight;
  camera.updateProjectionMatrix();
  requestAnimationFrame(draw);
});
function draw() {
  const start = performance.now();
  light.position.copy(camera.position);
  renderer.render(world, camera);
  state.drawMs = performance.now() - start;
}

// The model choice and one set of sliders per moved segment.
const modelSelect = document.getElementById("model");
for (const m of scene.models) modelSelect.add(new Option(m, m));
const motions = {};
const sliderNames = ["tx", "ty", "tz", "rx", "ry", "rz"];
const segmentsDiv = document.getElementById("segments");
for (const segment of scene.segments) {
  motions[segment.name] = [0, 0, 0, 0, 0, 0];
  const fieldset = document.createElement("fieldset");
  fieldset.innerHTML = `<legend>${segment.name}</legend>`;
  sliderNames.forEach((name, k) => {
    const limit = k < 3 ? scene.limits.translation : scene.limits.rotation;
    const label = document.createElement("label");
    label.className = "slider";
    label.innerHTML = `<span>${name}</span><input type="range" min="${-limit}" max="${limit}" ` +
      `step="${k < 3 ? 0.1 : 0.5}" value="0" data-segment="${segment.name}" data-k="${k}">` +
      `<output>0</output>`;
    const input = label.querySelector("input");
    input.addEventListener("input", () => {
      motions[segment.name][k] = Number(input.value);
      label.querySelector("output").textContent = input.value + (k < 3 ? " mm" : "°");
      request();
    });
    fieldset.appendChild(label);
  });
  segmentsDiv.appendChild(fieldset);
}
modelSelect.addEventListener("change", request);
document.getElementById("reset").addEventListener("click", () => {
  for (const input of segmentsDiv.querySelectorAll("input")) {
    input.value = 0;
    input.dispatchEvent(new Event("input"));
  }
});
for (const radio of document.querySelectorAll("input[name=show]"))
  radio.addEventListener("change", showChoice);
// Distances are computed by the server on request: a change asks again.
for (const radio of document.querySelectorAll("input[name=colour]"))
  radio.addEventListener("change", request);
function colourChoice() {
  return document.querySelector("input[name=colour]:checked").value;
}

// Re-plans: one in flight at a time; a slider moved meanwhile sends its
// latest value when the answer is in (the page never queues stale plans).
const socket = new WebSocket(`ws://${location.host}/replan`);
socket.binaryType = "arraybuffer";
let displacement = new Float32Array(3 * moving.length);
let distance = null; // of the moving points, when asked for
function request() {
  state.pending = { id: state.nextId++, model: modelSelect.value,
                    motions: structuredClone(motions), sent: 0, distance: colourChoice() === "distance" };
  if (!state.inFlight && socket.readyState === WebSocket.OPEN) send();
}
function send() {
  const plan = state.pending;
  state.pending = null;
  plan.sent = performance.now();
  state.inFlight = plan;
  socket.send(JSON.stringify({ id: plan.id, model: plan.model, motions: plan.motions,
                               distance: plan.distance }));
}
socket.onopen = () => { state.ready = true; request(); };
socket.onmessage = (event) => {
  const plan = state.inFlight;
  state.inFlight = null;
  if (typeof event.data === "string") {
    const answer = JSON.parse(event.data);
    state.errors.push(answer.error);
    document.getElementById("error").textContent = "server: " + answer.error;
  } else {
    state.answerMs = performance.now() - plan.sent;
    const head = new DataView(event.data, 0, 24);
    const combination = head.getFloat32(4, true), mapping = head.getFloat32(8, true);
    const distanceMs = head.getFloat32(12, true), count = head.getUint32(16, true);
    displacement = new Float32Array(event.data, 24, 3 * count);
    distance = head.getUint32(20, true) & 1 ? new Float32Array(event.data, 24 + 12 * count, count) : null;
    document.getElementById("error").textContent = "";
    showChoice();
    // The latency ends when the frame with the new face has been drawn.
    requestAnimationFrame(() => {
      const latency = performance.now() - plan.sent;
      state.latencies.push(latency);
      state.replans += 1;
      state.lastId = plan.id;
      document.getElementById("status").textContent =
        `re-plan ${plan.id}: server ${combination.toFixed(2)} ms (combination) + ` +
        `${mapping.toFixed(2)} ms (mapping)` +
        (distance ? ` + ${distanceMs.toFixed(1)} ms (distances)` : "") +
        `\nslider to face ${latency.toFixed(1)} ms\n` +
        `largest |u| ${state.lastMax.toFixed(2)} mm`;
    });
  }
  if (state.pending) send();
};
socket.onclose = () => {
  state.inFlight = null;
  state.ready = false;
  document.getElementById("error").textContent = "connection to softface serve closed: reload the page";
};

function showChoice() {
  const show = document.querySelector("input[name=show]:checked").value;
  state.showing = show;
  face.visible = show !== "post";
  if (postMesh) postMesh.visible = show === "post";
  const updateStart = performance.now();
  const position = face.geometry.attributes.position.array;
  const colour = face.geometry.attributes.color.array;
  let largest = 0;
  for (let i = 0; i < displacement.length; i += 3) {
    const u = Math.hypot(displacement[i], displacement[i + 1], displacement[i + 2]);
    largest = Math.max(largest, u);
  }
  state.lastMax = largest;
  const scale = Math.max(largest, 1e-9);
  const moved = show === "predicted";
  // Signed distances on a fixed -3..3 mm scale (the paper's Fig. 10).
  const byDistance = moved && distance !== null && restDistance !== null;
  const distanceColour = (d) => colourMap((d + 3) / 6);
  // Points that never move: no motion, or their distance at rest; grey in
  // the other views.
  const fill = `${show} ${byDistance}`;
  if (state.colouredFor !== fill) {
    for (let p = 0, i = 0; i < colour.length; ++p, i += 3) {
      const [r, g, b] = !moved ? [0.85, 0.85, 0.85]
                              : byDistance ? distanceColour(restDistance[p]) : colourMap(0);
      colour[i] = r; colour[i + 1] = g; colour[i + 2] = b;
    }
    state.colouredFor = fill;
  }
  for (let k = 0, j = 0; k < moving.length; ++k, j += 3) {
    const i = 3 * moving[k];
    const dx = displacement[j], dy = displacement[j + 1], dz = displacement[j + 2];
    position[i] = rest.positions[i] + (moved ? dx : 0);
    position[i + 1] = rest.positions[i + 1] + (moved ? dy : 0);
    position[i + 2] = rest.positions[i + 2] + (moved ? dz : 0);
    const [r, g, b] = !moved ? [0.85, 0.85, 0.85]
                      : byDistance ? distanceColour(distance[k])
                                   : colourMap(Math.sqrt(dx * dx + dy * dy + dz * dz) / scale);
    colour[i] = r; colour[i + 1] = g; colour[i + 2] = b;
  }
  state.updateMs = performance.now() - updateStart;
  face.geometry.attributes.position.needsUpdate = true;
  face.geometry.attributes.color.needsUpdate = true;
  state.colouredBy = byDistance ? "distance" : "magnitude";
  document.getElementById("legend-low").textContent = byDistance ? "-3" : "0";
  document.getElementById("legend-high").textContent = byDistance ? "3" : largest.toFixed(2);
  document.getElementById("legend-title").textContent = byDistance ? "distance mm" : "|u| mm";
  draw();
}

// The legend's colour bar.
const bar = document.querySelector("#legend canvas").getContext("2d");
for (let x = 0; x < 200; ++x) {
  const [r, g, b] = colourMap(x / 199);
  bar.fillStyle = `rgb(${255 * r},${255 * g},${255 * b})`;
  bar.fillRect(x, 0, 1, 12);
}
draw();
