/**
 * The 3D viewer of an asset's parts (three.js): each part's OBJ (object frame, Z up, metres) in
 * its own colour, an arrow per movable joint, and the joints animated through their ranges.
 *
 * Imported dynamically by the asset page, so a missing three.js only costs the viewer. Frames
 * are drawn only when something changed or while animating, and never while the tab is hidden
 * or the view is scrolled away.
 */

import * as THREE from 'three';
import { OBJLoader } from 'three/addons/loaders/OBJLoader.js';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';
import { KinematicTree } from './kinematics.js';
import { hsl } from './palette.js';

/** Seconds for one sweep of a joint's range and back (one turn of a continuous joint). */
const PERIOD_S = 3;
const FIELD_OF_VIEW_DEG = 35;
const ARROW_COLORS = { revolute: 0xe8590c, continuous: 0xc2255c, prismatic: 0x1098ad };
const BACKGROUND = 0xf3f5f8;

/**
 * Loads every part of `record` and shows them in `container` (which gets the canvas).
 * @param {HTMLElement} container
 * @param {{record: object, loadObj: (partId: number) => Promise<string>}} options `loadObj`
 *   answers the text of `parts/part_<id>.obj`.
 * @returns {Promise<Viewer>}
 */
export async function createViewer(container, { record, loadObj }) {
  // Fetch first: a failed download then leaves no WebGL context behind.
  const texts = await Promise.all(record.parts.map((part) => loadObj(part.id)));
  return new Viewer(container, record, texts);
}

export class Viewer {
  constructor(container, record, objTexts) {
    this.container = container;
    this.tree = new KinematicTree(record);
    this.enabled = new Set(this.tree.movable.map((j) => j.name));
    this.animating = true;
    this.clockS = 0;
    this.lastFrameMs = null;
    this.frame = null;
    this.disposed = false;

    this.renderer = createRenderer();
    container.append(this.renderer.domElement);
    this.scene = new THREE.Scene();
    this.scene.background = new THREE.Color(BACKGROUND);
    this.nodes = addParts(this.scene, record, objTexts);
    /** How many parts were loaded (the viewer's `data-parts`). */
    this.partCount = this.nodes.size;

    const box = this.sweptBox();
    this.camera = frameCamera(box);
    this.scene.add(groundGrid(box), ...lights(box));
    this.arrows = addJointArrows(this.tree, record, this.nodes, this.scene, box);

    this.controls = new OrbitControls(this.camera, this.renderer.domElement);
    this.controls.target.copy(box.getCenter(new THREE.Vector3()));
    this.controls.update();
    this.controls.addEventListener('change', () => this.requestFrame());

    this.draw = (nowMs) => this.drawFrame(nowMs);
    this.onVisibility = () => {
      this.lastFrameMs = null;
      this.requestFrame();
    };
    document.addEventListener('visibilitychange', this.onVisibility);
    this.resizer = new ResizeObserver(() => this.resize());
    this.resizer.observe(container);
    // No frames while scrolled out of view either.
    this.onScreen = true;
    this.visibility = new IntersectionObserver((entries) => {
      this.onScreen = entries[entries.length - 1].isIntersecting;
      this.lastFrameMs = null;
      this.requestFrame();
    });
    this.visibility.observe(container);
    this.resize();
  }

  /** Starts or pauses the joint animation (a paused joint keeps its position). */
  setAnimating(on) {
    this.animating = on;
    this.lastFrameMs = null;
    this.requestFrame();
  }

  /** Includes a joint in the animation or puts it back at rest. */
  setJointEnabled(name, on) {
    if (on) this.enabled.add(name);
    else this.enabled.delete(name);
    this.requestFrame();
  }

  /** Shows or hides the joint arrows. */
  setAxesVisible(on) {
    for (const arrow of this.arrows) arrow.visible = on;
    this.requestFrame();
  }

  /** Stops drawing and frees the GPU resources and the WebGL context. */
  dispose() {
    this.disposed = true;
    if (this.frame !== null) cancelAnimationFrame(this.frame);
    document.removeEventListener('visibilitychange', this.onVisibility);
    this.resizer.disconnect();
    this.visibility.disconnect();
    this.controls.dispose();
    this.scene.traverse((object) => {
      object.geometry?.dispose();
      const materials = Array.isArray(object.material) ? object.material : [object.material];
      for (const material of materials) material?.dispose();
    });
    this.renderer.dispose();
    this.renderer.forceContextLoss();
    this.renderer.domElement.remove();
  }

  requestFrame() {
    if (this.frame === null && !this.disposed && !document.hidden && this.onScreen) {
      this.frame = requestAnimationFrame(this.draw);
    }
  }

  drawFrame(nowMs) {
    this.frame = null;
    if (this.disposed) return;
    if (this.animating && this.lastFrameMs !== null) {
      // At most 0.1 s per frame: the animation resumes where it was after a pause or hidden tab.
      this.clockS += Math.min(nowMs - this.lastFrameMs, 100) / 1000;
    }
    this.lastFrameMs = nowMs;
    this.pose(this.clockS);
    this.renderer.render(this.scene, this.camera);
    if (this.animating && this.enabled.size > 0) this.requestFrame();
  }

  /** Moves every part to its pose at `tS` seconds into the animation. */
  pose(tS) {
    const q = new Map();
    for (const joint of this.tree.movable) {
      if (this.enabled.has(joint.name)) q.set(joint.name, this.tree.positionAt(joint, tS, PERIOD_S));
    }
    for (const [id, pose] of this.tree.poses(q)) {
      const node = this.nodes.get(id);
      if (!node) continue;
      node.matrix.copy(pose);
      node.matrixWorldNeedsUpdate = true;
    }
  }

  /** The bounding box of the parts over a whole animation period, so moving parts stay in view. */
  sweptBox() {
    const box = new THREE.Box3();
    for (let i = 0; i < 8; i += 1) {
      this.pose((i / 8) * PERIOD_S);
      this.scene.updateMatrixWorld(true);
      box.union(new THREE.Box3().setFromObject(this.scene));
    }
    this.pose(0);
    if (box.isEmpty()) box.set(new THREE.Vector3(-0.5, -0.5, 0), new THREE.Vector3(0.5, 0.5, 1));
    return box;
  }

  resize() {
    const width = this.container.clientWidth;
    const height = this.container.clientHeight;
    if (width === 0 || height === 0) return;
    this.renderer.setSize(width, height, false);
    this.camera.aspect = width / height;
    this.camera.updateProjectionMatrix();
    this.requestFrame();
  }
}

function createRenderer() {
  let renderer;
  try {
    // preserveDrawingBuffer: the canvas can be read back (snapshots, the browser test).
    renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
  } catch (e) {
    throw new Error(`WebGL is not available in this browser (${e.message})`);
  }
  renderer.setPixelRatio(Math.min(window.devicePixelRatio || 1, 2));
  renderer.domElement.setAttribute('aria-label', '3D view of the parts; drag to orbit, scroll to zoom, right-drag to pan');
  renderer.domElement.setAttribute('role', 'img');
  return renderer;
}

/** One node per part (its pose, set each frame) holding the part's meshes and their edges. */
function addParts(scene, record, objTexts) {
  const loader = new OBJLoader();
  const nodes = new Map();
  record.parts.forEach((part, i) => {
    const { h, s, l } = hsl(i);
    const color = new THREE.Color().setHSL(h, s, l, THREE.SRGBColorSpace);
    const material = new THREE.MeshStandardMaterial({
      color, roughness: 0.65, metalness: 0.05, flatShading: true, side: THREE.DoubleSide,
      polygonOffset: true, polygonOffsetFactor: 1, polygonOffsetUnits: 1,
    });
    const edgeMaterial = new THREE.LineBasicMaterial({ color: color.clone().multiplyScalar(0.45) });
    const object = loader.parse(objTexts[i]);
    const meshes = [];
    object.traverse((child) => {
      if (child.isMesh) meshes.push(child);
    });
    for (const mesh of meshes) {
      const loaded = Array.isArray(mesh.material) ? mesh.material : [mesh.material];
      loaded.forEach((m) => m.dispose());
      mesh.material = material;
      mesh.add(new THREE.LineSegments(new THREE.EdgesGeometry(mesh.geometry, 30), edgeMaterial));
    }
    const node = new THREE.Group();
    node.name = part.name;
    node.matrixAutoUpdate = false;
    node.add(object);
    scene.add(node);
    nodes.set(part.id, node);
  });
  return nodes;
}

/**
 * A camera with Z up, looking at the box from the front (−y) right and above, at the distance
 * where the box's bounding sphere just fits the vertical field of view (so the whole box shows
 * from any side in a view at least as wide as it is high).
 */
function frameCamera(box) {
  const centre = box.getCenter(new THREE.Vector3());
  const radius = Math.max(box.getSize(new THREE.Vector3()).length() / 2, 0.01);
  const camera = new THREE.PerspectiveCamera(FIELD_OF_VIEW_DEG, 1, radius / 100, radius * 100);
  camera.up.set(0, 0, 1);
  const distance = radius / Math.sin(THREE.MathUtils.degToRad(FIELD_OF_VIEW_DEG) / 2);
  const direction = new THREE.Vector3(0.9, -1.6, 0.9).normalize();
  camera.position.copy(centre).addScaledVector(direction, distance);
  camera.lookAt(centre);
  return camera;
}

/** A grid on the plane z = box bottom, in round steps of 10ⁿ, 2·10ⁿ or 5·10ⁿ metres. */
function groundGrid(box) {
  const size = box.getSize(new THREE.Vector3());
  const extent = 2 * Math.max(size.x, size.y, 0.01);
  const raw = extent / 16;
  const power = 10 ** Math.floor(Math.log10(raw));
  const cell = [1, 2, 5, 10].map((m) => m * power).find((c) => c >= raw);
  const divisions = Math.ceil(extent / cell);
  const grid = new THREE.GridHelper(divisions * cell, divisions, 0x8a94a6, 0xc9cfd8);
  grid.rotation.x = Math.PI / 2; // GridHelper lies in XZ; the ground is XY.
  const centre = box.getCenter(new THREE.Vector3());
  grid.position.set(centre.x, centre.y, box.min.z);
  return grid;
}

function lights(box) {
  const radius = Math.max(box.getSize(new THREE.Vector3()).length(), 0.1);
  const sky = new THREE.HemisphereLight(0xffffff, 0x6b7280, 1.6);
  sky.position.set(0, 0, 1);
  const sun = new THREE.DirectionalLight(0xffffff, 1.8);
  sun.position.copy(box.getCenter(new THREE.Vector3())).add(new THREE.Vector3(1, -2, 3).multiplyScalar(radius));
  return [sky, sun, new THREE.AmbientLight(0xffffff, 0.3)];
}

/**
 * An arrow per movable joint along its axis: through the pivot for a rotation, from the child's
 * centre for a slide. It belongs to the parent part, so it moves with whatever moves the parent.
 */
function addJointArrows(tree, record, nodes, scene, box) {
  const length = Math.max(box.getSize(new THREE.Vector3()).length() * 0.3, 0.02);
  const bounds = new Map(record.parts.map((p) => [p.id, p.bounds_in_object_m]));
  return tree.movable.map((joint) => {
    let origin;
    if (joint.kind === 'prismatic') {
      const [lo, hi] = bounds.get(joint.child) ?? [[0, 0, 0], [0, 0, 0]];
      origin = new THREE.Vector3(...lo).add(new THREE.Vector3(...hi)).multiplyScalar(0.5);
    } else {
      origin = joint.pivot.clone().addScaledVector(joint.axis, -length / 2);
    }
    const arrow = new THREE.ArrowHelper(joint.axis, origin, length, ARROW_COLORS[joint.kind] ?? 0x000000,
      length * 0.2, length * 0.1);
    arrow.name = `joint ${joint.name}`;
    // Drawn over the parts: an axis inside a body should still show.
    for (const part of [arrow.line, arrow.cone]) {
      part.material.depthTest = false;
      part.renderOrder = 10;
    }
    (nodes.get(joint.parent) ?? scene).add(arrow);
    return arrow;
  });
}
