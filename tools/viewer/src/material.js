// The field material: two neighbouring time steps arrive as normalized uint16 attributes
// (valueA, valueB) and are blended on the GPU with the uniform mixT, then mapped through the
// colormap texture. One uniforms object is shared by the 3D and the 2D material.
import * as THREE from 'three';

export function fieldUniforms(texture) {
  return {
    cmap: { value: texture },
    mixT: { value: 0 },
    dataLo: { value: 0 }, // the field's stored range: value = dataLo + q * (dataHi - dataLo)
    dataHi: { value: 1 },
    rangeMin: { value: 0 }, // the colour range chosen by the user
    rangeMax: { value: 1 },
  };
}

const vertexShader = /* glsl */ `
  attribute float valueA;
  attribute float valueB;
  uniform float mixT;
  uniform float dataLo;
  uniform float dataHi;
  varying float vValue;
  #ifdef LIT
  varying vec3 vNormal;
  #endif
  void main() {
    vValue = dataLo + mix(valueA, valueB, mixT) * (dataHi - dataLo);
    #ifdef LIT
    vNormal = normalize(normalMatrix * normal);
    #endif
    gl_Position = projectionMatrix * modelViewMatrix * vec4(position, 1.0);
  }
`;

const fragmentShader = /* glsl */ `
  uniform sampler2D cmap;
  uniform float rangeMin;
  uniform float rangeMax;
  varying float vValue;
  #ifdef LIT
  varying vec3 vNormal;
  #endif
  void main() {
    float s = clamp((vValue - rangeMin) / max(rangeMax - rangeMin, 1e-30), 0.0, 1.0);
    vec3 color = texture2D(cmap, vec2(s * (255.0 / 256.0) + 0.5 / 256.0, 0.5)).rgb;
    #ifdef LIT
    // Headlight: the camera looks down -z in view space; back faces (inside the vessel) are lit
    // from their own side.
    vec3 n = normalize(vNormal) * (gl_FrontFacing ? 1.0 : -1.0);
    color *= 0.45 + 0.55 * abs(n.z);
    #endif
    gl_FragColor = vec4(color, 1.0);
  }
`;

export function fieldMaterial(uniforms, lit) {
  return new THREE.ShaderMaterial({
    uniforms,
    vertexShader,
    fragmentShader,
    defines: lit ? { LIT: 1 } : {},
    side: THREE.DoubleSide,
    polygonOffset: true, // the seam lines are drawn on top
    polygonOffsetFactor: 1,
    polygonOffsetUnits: 1,
  });
}

// Picking material: writes the vertex's normalized map coordinates (u, v in [0, 1]) with 12 bits
// each into RGB, alpha = 1 marks a hit. Read back one pixel to know which map point is under the
// mouse in the 3D view.
const pickVertex = /* glsl */ `
  attribute vec2 mapUv;
  varying vec2 vMapUv;
  void main() {
    vMapUv = mapUv;
    gl_Position = projectionMatrix * modelViewMatrix * vec4(position, 1.0);
  }
`;
const pickFragment = /* glsl */ `
  varying vec2 vMapUv;
  void main() {
    vec2 q = floor(clamp(vMapUv, 0.0, 1.0) * 4095.0 + 0.5);
    float r = floor(q.x / 16.0);
    float g = mod(q.x, 16.0) * 16.0 + floor(q.y / 256.0);
    float b = mod(q.y, 256.0);
    gl_FragColor = vec4(r, g, b, 255.0) / 255.0;
  }
`;

export function pickMaterial() {
  return new THREE.ShaderMaterial({
    vertexShader: pickVertex,
    fragmentShader: pickFragment,
    side: THREE.DoubleSide,
    blending: THREE.NoBlending,
  });
}

export function decodePick(pixel) {
  if (pixel[3] < 128) return null;
  const qx = pixel[0] * 16 + (pixel[1] >> 4);
  const qy = (pixel[1] & 15) * 256 + pixel[2];
  return [qx / 4095, qy / 4095];
}
