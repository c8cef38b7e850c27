// The 3D view (three.js): the arm as a simple-solid stick model from the
// model's kinematics and the live axis angles, the base and tool frames,
// the executed TCP path (travel faint and dashed) and the planned paths. Renders only when
// something changed (no animation loop).
import * as THREE from "./vendor/three.module.js";
import { OrbitControls } from "./vendor/OrbitControls.js";
import { frameMatrix, skeleton, mul, apply } from "./kinematics.js";
import { runs } from "./projections.js";

const EXECUTED = 0x1f6feb;
const PLANNED = 0xf08c00;

/**
 * Growable line segments (two vertices each) with the path length at each
 * vertex, so a dashed material dashes along the whole path, not per
 * segment; buffers doubled when full.
 */
class Segments {
  constructor(scene, material) {
    this.geometry = new THREE.BufferGeometry();
    this.capacity = 0;
    this.count = 0;
    this.line = new THREE.LineSegments(this.geometry, material);
    this.line.frustumCulled = false;
    scene.add(this.line);
    this.reserve(1024);
  }
  reserve(n) {
    if (n <= this.capacity) return;
    let cap = Math.max(this.capacity, 1024);
    while (cap < n) cap *= 2;
    const pos = new Float32Array(cap * 6);
    const dist = new Float32Array(cap * 2);
    if (this.pos) {
      pos.set(this.pos.array.subarray(0, this.count * 6));
      dist.set(this.dist.array.subarray(0, this.count * 2));
    }
    this.pos = new THREE.BufferAttribute(pos, 3);
    this.dist = new THREE.BufferAttribute(dist, 1);
    this.geometry.setAttribute("position", this.pos);
    this.geometry.setAttribute("lineDistance", this.dist);
    this.capacity = cap;
  }
  /** Adds the segment a→b; `d0`, `d1` = the path length at a and b. */
  push(a, b, d0, d1) {
    this.reserve(this.count + 1);
    this.pos.array.set(a, this.count * 6);
    this.pos.array.set(b, this.count * 6 + 3);
    this.dist.array[this.count * 2] = d0;
    this.dist.array[this.count * 2 + 1] = d1;
    this.count++;
  }
  commit() {
    this.pos.needsUpdate = true;
    this.dist.needsUpdate = true;
    this.geometry.setDrawRange(0, this.count * 2);
  }
  clear() {
    this.count = 0;
    this.commit();
  }
}

/** Travel (pen up) is drawn faint and dashed: 3D dashes in mm. */
const travelMaterial = (color, opacity) => new THREE.LineDashedMaterial({ color, dashSize: 6, gapSize: 5, transparent: true, opacity });

/** The 3D scene in `container`. */
export class ArmView {
  constructor(container) {
    this.container = container;
    this.renderer = new THREE.WebGLRenderer({ antialias: true });
    this.renderer.setPixelRatio(window.devicePixelRatio || 1);
    container.appendChild(this.renderer.domElement);
    this.scene = new THREE.Scene();
    this.scene.background = new THREE.Color(0xf7f8fa);
    this.camera = new THREE.PerspectiveCamera(40, 1, 1, 20000);
    this.camera.up.set(0, 0, 1);
    this.camera.position.set(1200, -1400, 900);
    this.controls = new OrbitControls(this.camera, this.renderer.domElement);
    this.controls.target.set(200, 0, 300);
    this.controls.addEventListener("change", () => this.render());
    // On touch screens the view starts still, so a swipe scrolls the page;
    // the page offers a button to turn and zoom (see setInteractive).
    if (window.matchMedia("(pointer: coarse)").matches) this.setInteractive(false);
    this.scene.add(new THREE.HemisphereLight(0xffffff, 0x667788, 2.2));
    const sun = new THREE.DirectionalLight(0xffffff, 1.5);
    sun.position.set(1000, -800, 2000);
    this.scene.add(sun);
    const grid = new THREE.GridHelper(2000, 20, 0xb0b8c4, 0xd8dde4);
    grid.rotation.x = Math.PI / 2; // the floor is the XY plane, Z up
    this.scene.add(grid);
    this.world = new THREE.AxesHelper(150);
    this.scene.add(this.world);
    this.baseFrame = this.frameHelper(120);
    this.toolFrame = this.frameHelper(80);
    this.links = [];
    this.joints = [];
    this.linkMaterial = new THREE.MeshStandardMaterial({ color: 0xff7a00, metalness: 0.1, roughness: 0.6 });
    this.jointMaterial = new THREE.MeshStandardMaterial({ color: 0x39424e, roughness: 0.5 });
    // The executed path: strokes solid, travel faint and dashed.
    this.ink = new Segments(this.scene, new THREE.LineBasicMaterial({ color: EXECUTED }));
    this.travel = new Segments(this.scene, travelMaterial(EXECUTED, 0.35));
    this.executedCount = 0;
    this.lastPoint = null;
    this.pathLength = 0;
    this.planned = new THREE.Group();
    this.scene.add(this.planned);
    this.baseMatrix = frameMatrix([0, 0, 0, 0, 0, 0]);
    new ResizeObserver(() => this.resize()).observe(container);
    this.resize();
  }

  /** Lets touches and the mouse turn and zoom the view (true), or scroll the page (false). */
  setInteractive(on) {
    this.controls.enabled = on;
    this.renderer.domElement.style.touchAction = on ? "none" : "pan-y";
  }

  /** True when the view turns and zooms with touches and the mouse. */
  get interactive() {
    return this.controls.enabled;
  }

  frameHelper(size) {
    const h = new THREE.AxesHelper(size);
    h.matrixAutoUpdate = false;
    this.scene.add(h);
    return h;
  }

  resize() {
    const w = this.container.clientWidth || 400;
    const h = this.container.clientHeight || 300;
    this.renderer.setSize(w, h, false);
    this.camera.aspect = w / h;
    this.camera.updateProjectionMatrix();
    this.render();
  }

  /** Frames the camera on a robot of this reach. */
  fit(model) {
    const { c1, c2, c3, c4, a1 } = model.opw_mm;
    const reach = a1 + c2 + c3 + c4;
    this.camera.position.set(reach * 1.3, -reach * 1.5, c1 + reach * 0.9);
    this.controls.target.set(reach * 0.3, 0, c1 * 0.8);
    this.controls.update();
    const r = Math.max(10, reach / 30);
    this.radius = r;
  }

  /** Draws the arm for the model and these axis angles; base and tool as KUKA frames. */
  setPose(model, axes, tool, base) {
    const { points, flange } = skeleton(model, axes);
    const r = this.radius || 12;
    while (this.links.length < points.length - 1) {
      const link = new THREE.Mesh(new THREE.CylinderGeometry(1, 1, 1, 16), this.linkMaterial);
      this.scene.add(link);
      this.links.push(link);
    }
    while (this.joints.length < points.length) {
      const joint = new THREE.Mesh(new THREE.SphereGeometry(1, 16, 12), this.jointMaterial);
      this.scene.add(joint);
      this.joints.push(joint);
    }
    const up = new THREE.Vector3(0, 1, 0);
    for (let i = 0; i < points.length - 1; i++) {
      const a = new THREE.Vector3(...points[i]);
      const b = new THREE.Vector3(...points[i + 1]);
      const d = b.clone().sub(a);
      const link = this.links[i];
      const len = d.length();
      link.visible = len > 1e-6;
      link.position.copy(a).addScaledVector(d, 0.5);
      link.quaternion.setFromUnitVectors(up, d.normalize());
      const w = i === 0 ? r * 2.2 : r * (1.4 - i * 0.12);
      link.scale.set(w, len, w);
    }
    points.forEach((p, i) => {
      this.joints[i].position.set(...p);
      this.joints[i].scale.setScalar(r * (i === 0 ? 2.6 : 1.7 - i * 0.12));
    });
    this.baseMatrix = frameMatrix(base);
    setMatrix(this.baseFrame, this.baseMatrix);
    setMatrix(this.toolFrame, mul(flange, frameMatrix(tool)));
    this.render();
  }

  /** Base-frame points → robot root frame. */
  toWorld(points) {
    return points.map((p) => apply(this.baseMatrix, p));
  }

  /** Adds executed TCP points (base frame); `travel[i]` = the segment to point i is travel. */
  addExecuted(points, travel = []) {
    const world = this.toWorld(points);
    for (let i = 0; i < world.length; i++) {
      const p = world[i];
      if (this.lastPoint) {
        const a = this.lastPoint;
        const len = Math.hypot(p[0] - a[0], p[1] - a[1], p[2] - a[2]);
        (travel[i] ? this.travel : this.ink).push(a, p, this.pathLength, this.pathLength + len);
        this.pathLength += len;
      }
      this.lastPoint = p;
      this.executedCount++;
    }
    this.ink.commit();
    this.travel.commit();
    this.render();
  }

  /** Replaces the executed path (base frame). */
  setExecuted(points, travel = []) {
    this.ink.clear();
    this.travel.clear();
    this.lastPoint = null;
    this.pathLength = 0;
    this.executedCount = 0;
    this.addExecuted(points, travel);
  }

  /** Shows the planned paths [{points, travel}] (base frame), replacing the previous ones: strokes dashed, travel fainter. */
  setPlanned(plans) {
    for (const c of [...this.planned.children]) {
      c.geometry.dispose();
      c.material.dispose();
      this.planned.remove(c);
    }
    for (const plan of plans) {
      for (const run of runs(plan.points, plan.travel)) {
        const g = new THREE.BufferGeometry().setFromPoints(this.toWorld(run.points).map((p) => new THREE.Vector3(...p)));
        const material = run.travel ? travelMaterial(PLANNED, 0.35) : new THREE.LineDashedMaterial({ color: PLANNED, dashSize: 6, gapSize: 4 });
        const line = new THREE.Line(g, material);
        line.computeLineDistances();
        line.userData.travel = run.travel;
        this.planned.add(line);
      }
    }
    this.render();
  }

  /** Renders once at the next frame (coalesces many updates). */
  render() {
    if (this.pending) return;
    this.pending = true;
    requestAnimationFrame(() => {
      this.pending = false;
      this.renderNow();
    });
  }

  /** Renders now (benchmarks and screenshots). */
  renderNow() {
    this.renderer.render(this.scene, this.camera);
    this.frames = (this.frames || 0) + 1;
  }
}

function setMatrix(object, m) {
  object.matrix.set(...m);
  object.matrixWorldNeedsUpdate = true;
}
