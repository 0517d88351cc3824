// The 2D view: the flattened map with an orthographic camera, wheel zoom at the cursor and drag
// pan, and a ring marker for the linked hover.
import * as THREE from 'three';
import { fieldMaterial } from './material.js';

export class View2d {
  constructor(canvas, data, shared, onChange) {
    this.canvas = canvas;
    this.onChange = onChange;
    this.renderer = new THREE.WebGLRenderer({ canvas, antialias: true, preserveDrawingBuffer: false });
    this.renderer.setPixelRatio(window.devicePixelRatio || 1);
    this.renderer.setClearColor(0x1b1e24);
    this.scene = new THREE.Scene();

    const n = data.uv.length / 2;
    const flat = new Float32Array(3 * n);
    for (let i = 0; i < n; i++) {
      flat[3 * i] = data.uv[2 * i];
      flat[3 * i + 1] = data.uv[2 * i + 1];
    }
    const geometry = new THREE.BufferGeometry();
    geometry.setIndex(shared.index);
    geometry.setAttribute('position', new THREE.BufferAttribute(flat, 3));
    geometry.computeBoundingBox();
    this.geometry = geometry;
    this.mesh = new THREE.Mesh(geometry, fieldMaterial(shared.uniforms, false));
    this.scene.add(this.mesh);

    const box = geometry.boundingBox;
    this.centre = new THREE.Vector2((box.min.x + box.max.x) / 2, (box.min.y + box.max.y) / 2);
    this.extent = Math.max(box.max.x - box.min.x, box.max.y - box.min.y, 1e-30);
    const ring = new THREE.RingGeometry(this.extent * 0.008, this.extent * 0.014, 24);
    this.marker = new THREE.Mesh(ring, new THREE.MeshBasicMaterial({ color: 0xff00ff, depthTest: false }));
    this.marker.renderOrder = 10;
    this.marker.visible = false;
    this.scene.add(this.marker);

    this.camera = new THREE.OrthographicCamera(-1, 1, 1, -1, -10, 10);
    this.zoom = 1;
    this.pan = this.centre.clone();
    this.width = 1;
    this.height = 1;
    this.installControls();
  }

  installControls() {
    const canvas = this.canvas;
    canvas.addEventListener('wheel', (event) => {
      event.preventDefault();
      const before = this.toMap(event.offsetX, event.offsetY);
      this.zoom *= Math.exp(-event.deltaY * 0.0015);
      this.zoom = Math.min(Math.max(this.zoom, 0.2), 200);
      this.updateCamera();
      const after = this.toMap(event.offsetX, event.offsetY);
      this.pan.x += before[0] - after[0];
      this.pan.y += before[1] - after[1];
      this.updateCamera();
      this.onChange();
    }, { passive: false });
    let drag = null;
    canvas.addEventListener('pointerdown', (event) => {
      drag = { x: event.clientX, y: event.clientY };
      canvas.setPointerCapture(event.pointerId);
    });
    canvas.addEventListener('pointermove', (event) => {
      if (!drag) return;
      const scale = this.unitsPerPixel();
      this.pan.x -= (event.clientX - drag.x) * scale;
      this.pan.y += (event.clientY - drag.y) * scale;
      drag = { x: event.clientX, y: event.clientY };
      this.updateCamera();
      this.onChange();
    });
    const end = () => { drag = null; };
    canvas.addEventListener('pointerup', end);
    canvas.addEventListener('pointercancel', end);
    canvas.addEventListener('dblclick', () => this.resetView());
  }

  resetView() {
    this.zoom = 1;
    this.pan.copy(this.centre);
    this.updateCamera();
    this.onChange();
  }

  unitsPerPixel() {
    const fit = Math.max(this.extent / this.width, this.extent / this.height) * 1.08;
    return fit / this.zoom;
  }

  updateCamera() {
    const s = this.unitsPerPixel();
    const hw = (this.width * s) / 2, hh = (this.height * s) / 2;
    Object.assign(this.camera, { left: this.pan.x - hw, right: this.pan.x + hw, top: this.pan.y + hh, bottom: this.pan.y - hh });
    this.camera.updateProjectionMatrix();
  }

  resize(width, height) {
    this.width = Math.max(width, 1);
    this.height = Math.max(height, 1);
    this.renderer.setSize(width, height, false);
    this.updateCamera();
  }

  // Map coordinates of canvas pixel (x, y) in CSS pixels, and the reverse.
  toMap(x, y) {
    const s = this.unitsPerPixel();
    return [this.pan.x + (x - this.width / 2) * s, this.pan.y - (y - this.height / 2) * s];
  }

  toCanvas(u, v) {
    const s = this.unitsPerPixel();
    return [(u - this.pan.x) / s + this.width / 2, this.height / 2 - (v - this.pan.y) / s];
  }

  render() {
    this.renderer.render(this.scene, this.camera);
  }

  showMarker(point) {
    this.marker.visible = point !== null;
    if (point) this.marker.position.set(point[0], point[1], 0);
  }
}
