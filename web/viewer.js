// SPDX-License-Identifier: MIT
// Three.js view of the build platform, the placed model and the tool-path preview. Part frame: the
// platform is z = 0, +Z up, millimetres. Renders on demand (after a change or a camera move), not
// in a permanent loop, so an idle page costs nothing.
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';

export class Viewer {
  /**
   * @param {HTMLElement} host element the canvas fills
   * @throws when WebGL is unavailable (the caller shows a message and keeps the rest of the app)
   */
  constructor(host) {
    this.host = host;
    // Multisampling in a software renderer (SwiftShader, llvmpipe) costs several times the frame.
    this.renderer = new THREE.WebGLRenderer({ antialias: !isSoftwareRenderer(), preserveDrawingBuffer: false });
    this.renderer.setPixelRatio(Math.min(window.devicePixelRatio || 1, 2));
    this.renderer.setClearColor(0x1d2127);
    host.appendChild(this.renderer.domElement);

    this.scene = new THREE.Scene();
    this.camera = new THREE.PerspectiveCamera(40, 1, 0.5, 5000);
    this.camera.up.set(0, 0, 1);
    this.camera.position.set(160, -220, 170);

    this.controls = new OrbitControls(this.camera, this.renderer.domElement);
    this.controls.enableDamping = false;
    this.controls.addEventListener('change', () => this.requestRender());

    this.scene.add(new THREE.HemisphereLight(0xe8eef5, 0x40444c, 2.2));
    const sun = new THREE.DirectionalLight(0xffffff, 1.6);
    sun.position.set(120, -160, 300);
    this.scene.add(sun);

    this.bed = null;
    this.model = null;
    this.preview = null;
    this.machine = null;   // machine animation object (shown instead of bed, model and preview)
    this.modelVisible = true;
    this.renderPending = false;

    this.resizeObserver = new ResizeObserver(() => this.resize());
    this.resizeObserver.observe(host);
    this.resize();
    this.setBed([220, 220, 250]);
  }

  /** Platform grid and outline sized to the bed (mm, x by y by z), centred on the origin. */
  setBed(size) {
    if (this.bed) {
      this.scene.remove(this.bed);
      disposeTree(this.bed);
    }
    const [sx, sy] = size;
    const group = new THREE.Group();
    group.name = 'bed';
    const plate = new THREE.Mesh(
      new THREE.PlaneGeometry(sx, sy),
      new THREE.MeshBasicMaterial({ color: 0x2a3038, side: THREE.DoubleSide }),
    );
    plate.position.z = -0.05;
    group.add(plate);
    // Grid lines every 10 mm, bold every 50 mm, as one LineSegments.
    const pts = [];
    const colors = [];
    const minor = new THREE.Color(0x3a424d);
    const major = new THREE.Color(0x56606d);
    const pushLine = (x0, y0, x1, y1, bold) => {
      pts.push(x0, y0, 0, x1, y1, 0);
      const c = bold ? major : minor;
      colors.push(c.r, c.g, c.b, c.r, c.g, c.b);
    };
    for (let x = -Math.floor(sx / 20) * 10; x <= sx / 2 + 1e-9; x += 10) pushLine(x, -sy / 2, x, sy / 2, Math.abs(x) % 50 < 1e-9);
    for (let y = -Math.floor(sy / 20) * 10; y <= sy / 2 + 1e-9; y += 10) pushLine(-sx / 2, y, sx / 2, y, Math.abs(y) % 50 < 1e-9);
    pushLine(-sx / 2, -sy / 2, sx / 2, -sy / 2, true);
    pushLine(sx / 2, -sy / 2, sx / 2, sy / 2, true);
    pushLine(sx / 2, sy / 2, -sx / 2, sy / 2, true);
    pushLine(-sx / 2, sy / 2, -sx / 2, -sy / 2, true);
    const grid = new THREE.BufferGeometry();
    grid.setAttribute('position', new THREE.Float32BufferAttribute(pts, 3));
    grid.setAttribute('color', new THREE.Float32BufferAttribute(colors, 3));
    group.add(new THREE.LineSegments(grid, new THREE.LineBasicMaterial({ vertexColors: true })));
    // Axis marks at the origin: X red, Y green.
    const axes = new THREE.BufferGeometry();
    axes.setAttribute('position', new THREE.Float32BufferAttribute([0, 0, 0.02, 20, 0, 0.02, 0, 0, 0.02, 0, 20, 0.02], 3));
    axes.setAttribute('color', new THREE.Float32BufferAttribute([0.9, 0.3, 0.3, 0.9, 0.3, 0.3, 0.3, 0.85, 0.4, 0.3, 0.85, 0.4], 3));
    group.add(new THREE.LineSegments(axes, new THREE.LineBasicMaterial({ vertexColors: true })));
    this.bed = group;
    this.bedSize = size.slice();
    this.scene.add(group);
    this.requestRender();
  }

  /**
   * Show the placed model.
   * @param {{positions: Float32Array, indices: Uint32Array}} mesh #V*3 part-frame positions (mm), #F*3 indices
   * @param {{filledFrom?: number}} [options] faces from filledFrom on closed holes (the repair's
   *   first_filled_face): drawn in their own colour
   */
  setModel(mesh, { filledFrom } = {}) {
    this.clearModel();
    if (!mesh || !mesh.positions || mesh.positions.length === 0) return;
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute('position', new THREE.BufferAttribute(mesh.positions, 3));
    if (mesh.indices && mesh.indices.length) geometry.setIndex(new THREE.BufferAttribute(mesh.indices, 1));
    geometry.computeBoundingBox();
    geometry.computeBoundingSphere();
    // Flat shading derives normals in the fragment shader: no per-vertex normal pass on the main thread.
    const material = new THREE.MeshStandardMaterial({
      color: 0x8fb3d9, roughness: 0.65, metalness: 0.05, flatShading: true,
      side: THREE.DoubleSide, polygonOffset: true, polygonOffsetFactor: 1, polygonOffsetUnits: 1,
    });
    const faces = mesh.indices ? mesh.indices.length / 3 : mesh.positions.length / 9;
    let materials = material;
    if (Number.isInteger(filledFrom) && filledFrom >= 0 && filledFrom < faces) {
      // Two groups: the file's faces, then the faces the repair added (amber).
      geometry.addGroup(0, 3 * filledFrom, 0);
      geometry.addGroup(3 * filledFrom, 3 * (faces - filledFrom), 1);
      const filled = material.clone();
      filled.color.set(0xe0a040);
      filled.name = 'filled-holes';
      materials = [material, filled];
    }
    this.model = new THREE.Mesh(geometry, materials);
    this.model.name = 'model';
    this.model.userData.filledFaces = materials === material ? 0 : faces - filledFrom;
    this.scene.add(this.model);
    this.applyModelLook();
    this.requestRender();
  }

  clearModel() {
    if (!this.model) return;
    this.scene.remove(this.model);
    disposeTree(this.model);
    this.model = null;
    this.requestRender();
  }

  /** Replace the preview object (a THREE.Object3D owned by the viewer from now on; null clears). */
  setPreview(object) {
    if (this.preview) {
      this.scene.remove(this.preview);
      disposeTree(this.preview);
    }
    this.preview = object;
    if (object) this.scene.add(object);
    this.applyModelLook();
    this.requestRender();
  }

  /**
   * Show a machine model (a THREE.Object3D, e.g. MachineView.object; its owner disposes it) in
   * place of the bed, the model and the preview, and frame it; null returns to the part view.
   */
  setMachine(object) {
    if (this.machine) this.scene.remove(this.machine);
    this.machine = object || null;
    if (this.machine) this.scene.add(this.machine);
    this.applyModelLook();
    this.frame();
  }

  /** Model drawn solid alone, faint when a preview is shown, or hidden. */
  setModelVisible(visible) {
    this.modelVisible = visible;
    this.applyModelLook();
    this.requestRender();
  }

  applyModelLook() {
    const partView = !this.machine;
    if (this.bed) this.bed.visible = partView;
    if (this.preview) this.preview.visible = partView;
    if (!this.model) return;
    this.model.visible = this.modelVisible && partView;
    const ghost = !!this.preview;
    for (const m of Array.isArray(this.model.material) ? this.model.material : [this.model.material]) {
      m.transparent = ghost;
      m.opacity = ghost ? 0.18 : 1;
      m.depthWrite = !ghost;
      m.needsUpdate = true;
    }
  }

  /** Point the camera at the model's bounding box (or the bed when nothing is loaded). */
  frame() {
    const box = new THREE.Box3();
    if (this.machine) box.setFromObject(this.machine);
    else if (this.model) box.setFromObject(this.model);
    else if (this.preview) box.setFromObject(this.preview);
    if (box.isEmpty()) box.set(new THREE.Vector3(-60, -60, 0), new THREE.Vector3(60, 60, 40));
    const center = box.getCenter(new THREE.Vector3());
    const radius = Math.max(box.getSize(new THREE.Vector3()).length() / 2, 10);
    const dist = radius / Math.sin(THREE.MathUtils.degToRad(this.camera.fov / 2)) * 1.05;
    const dir = new THREE.Vector3(0.55, -0.75, 0.6).normalize();
    this.camera.position.copy(center).addScaledVector(dir, dist);
    this.camera.near = Math.max(dist / 100, 0.1);
    this.camera.far = dist * 20 + 2000;
    this.camera.updateProjectionMatrix();
    this.controls.target.copy(center);
    this.controls.update();
    this.requestRender();
  }

  resize() {
    const w = Math.max(this.host.clientWidth, 1);
    const h = Math.max(this.host.clientHeight, 1);
    this.renderer.setSize(w, h, false);
    this.camera.aspect = w / h;
    this.camera.updateProjectionMatrix();
    this.requestRender();
  }

  requestRender() {
    if (this.renderPending) return;
    this.renderPending = true;
    requestAnimationFrame(() => {
      this.renderPending = false;
      this.renderer.render(this.scene, this.camera);
    });
  }

  dispose() {
    this.resizeObserver.disconnect();
    this.controls.dispose();
    this.setPreview(null);
    this.clearModel();
    if (this.bed) disposeTree(this.bed);
    this.renderer.dispose();
    this.renderer.domElement.remove();
  }
}

/** True when WebGL runs on a CPU rasteriser (no GPU), judged from the unmasked renderer name. */
export function isSoftwareRenderer() {
  try {
    const gl = document.createElement('canvas').getContext('webgl2');
    if (!gl) return false;
    const ext = gl.getExtension('WEBGL_debug_renderer_info');
    const name = ext ? gl.getParameter(ext.UNMASKED_RENDERER_WEBGL) : gl.getParameter(gl.RENDERER);
    gl.getExtension('WEBGL_lose_context')?.loseContext();
    return /swiftshader|llvmpipe|softpipe|software/i.test(String(name));
  } catch {
    return false;
  }
}

/** Dispose every geometry and material under an object (replaced geometry must free GPU memory). */
export function disposeTree(object) {
  object.traverse((child) => {
    if (child.geometry) child.geometry.dispose();
    const mats = Array.isArray(child.material) ? child.material : child.material ? [child.material] : [];
    for (const m of mats) m.dispose();
  });
}
