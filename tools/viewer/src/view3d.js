// The 3D view: the cut mesh lit by a headlight, orbit/zoom/pan, the seam as lines, a hover marker,
// and GPU picking that returns the normalized map point under the mouse.
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';
import { fieldMaterial, pickMaterial, decodePick } from './material.js';

export class View3d {
  constructor(canvas, data, shared, onChange) {
    this.canvas = canvas;
    this.renderer = new THREE.WebGLRenderer({ canvas, antialias: true, preserveDrawingBuffer: false });
    this.renderer.setPixelRatio(window.devicePixelRatio || 1);
    this.renderer.setClearColor(0x1b1e24);
    this.scene = new THREE.Scene();

    const geometry = new THREE.BufferGeometry();
    geometry.setIndex(shared.index);
    geometry.setAttribute('position', new THREE.BufferAttribute(data.positions, 3));
    geometry.setAttribute('normal', new THREE.BufferAttribute(data.normals, 3));
    geometry.setAttribute('mapUv', new THREE.BufferAttribute(shared.mapUv, 2));
    geometry.computeBoundingSphere();
    this.geometry = geometry;
    this.mesh = new THREE.Mesh(geometry, fieldMaterial(shared.uniforms, true));
    this.scene.add(this.mesh);

    const seamGeometry = new THREE.BufferGeometry();
    seamGeometry.setAttribute('position', new THREE.BufferAttribute(data.seam, 3));
    this.seam = new THREE.LineSegments(seamGeometry, new THREE.LineBasicMaterial({ color: 0xff3b30 }));
    this.scene.add(this.seam);

    const sphere = geometry.boundingSphere;
    this.radius = sphere.radius;
    this.marker = new THREE.Mesh(
      new THREE.SphereGeometry(sphere.radius * 0.015, 16, 12),
      new THREE.MeshBasicMaterial({ color: 0xff00ff, depthTest: false }));
    this.marker.renderOrder = 10;
    this.marker.visible = false;
    this.scene.add(this.marker);

    this.camera = new THREE.PerspectiveCamera(40, 1, sphere.radius * 0.01, sphere.radius * 20);
    this.controls = new OrbitControls(this.camera, canvas);
    this.controls.addEventListener('change', () => onChange());
    this.resetCamera(data.meta.camera);

    this.pickMaterial = pickMaterial();
    this.pickTarget = new THREE.WebGLRenderTarget(1, 1);
    this.pickPixel = new Uint8Array(4);
  }

  // Looks at the mesh from `direction` (unit, relative to the centre), the whole mesh in view.
  resetCamera(direction) {
    const d = new THREE.Vector3(...(direction || [0, -1, 0])).normalize();
    const distance = this.radius / Math.sin(THREE.MathUtils.degToRad(this.camera.fov / 2));
    const centre = this.geometry.boundingSphere.center;
    this.camera.position.copy(centre).addScaledVector(d, distance * 1.05);
    this.camera.up.set(0, 0, 1);
    if (Math.abs(d.z) > 0.99) this.camera.up.set(0, 1, 0);
    this.controls.target.copy(centre);
    this.controls.update();
  }

  resize(width, height) {
    this.renderer.setSize(width, height, false);
    this.camera.aspect = width / Math.max(height, 1);
    this.camera.updateProjectionMatrix();
  }

  render() {
    this.renderer.render(this.scene, this.camera);
  }

  // Normalized map point [u, v] under canvas pixel (x, y) in CSS pixels, or null.
  pick(x, y) {
    const w = this.canvas.clientWidth, h = this.canvas.clientHeight;
    const ratio = this.renderer.getPixelRatio();
    this.camera.setViewOffset(w * ratio, h * ratio, Math.floor(x * ratio), Math.floor(y * ratio), 1, 1);
    const saved = { material: this.mesh.material, seam: this.seam.visible, marker: this.marker.visible };
    this.mesh.material = this.pickMaterial;
    this.seam.visible = false;
    this.marker.visible = false;
    const clear = this.renderer.getClearAlpha();
    const clearColor = this.renderer.getClearColor(new THREE.Color());
    this.renderer.setClearColor(0x000000, 0);
    this.renderer.setRenderTarget(this.pickTarget);
    this.renderer.render(this.scene, this.camera);
    this.renderer.readRenderTargetPixels(this.pickTarget, 0, 0, 1, 1, this.pickPixel);
    this.renderer.setRenderTarget(null);
    this.renderer.setClearColor(clearColor, clear);
    this.camera.clearViewOffset();
    this.mesh.material = saved.material;
    this.seam.visible = saved.seam;
    this.marker.visible = saved.marker;
    return decodePick(this.pickPixel);
  }

  showMarker(point) {
    this.marker.visible = point !== null;
    if (point) this.marker.position.set(point[0], point[1], point[2]);
  }
}
