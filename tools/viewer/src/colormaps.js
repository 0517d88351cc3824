// Colormaps as 256-entry lookup textures, plus the colorbar drawing.
import * as THREE from 'three';

// 17 evenly spaced samples of matplotlib's maps (sRGB), interpolated linearly.
const STOPS = {
  viridis: [0x440154, 0x48186a, 0x472d7b, 0x424086, 0x3b528b, 0x33638d, 0x2c728e, 0x26828e,
    0x21918c, 0x1fa088, 0x28ae80, 0x3fbc73, 0x5ec962, 0x84d44b, 0xaddc30, 0xd8e219, 0xfde725],
  'blue-white-red (diverging)': [0x053061, 0x175290, 0x2a71b2, 0x3f8ec0, 0x6bacd1, 0x9bc9e0,
    0xc2ddec, 0xe0ecf3, 0xf7f6f6, 0xfbe5d8, 0xfbccb4, 0xf5aa89, 0xe48066, 0xd05548, 0xba2832,
    0x930e26, 0x67001f],
};

export const COLORMAP_NAMES = Object.keys(STOPS);
export const DIVERGING = 'blue-white-red (diverging)';

// RGBA bytes, 256 entries.
export function colormapBytes(name) {
  const stops = STOPS[name];
  const bytes = new Uint8Array(256 * 4);
  for (let i = 0; i < 256; i++) {
    const x = (i / 255) * (stops.length - 1);
    const k = Math.min(Math.floor(x), stops.length - 2);
    const f = x - k;
    for (let c = 0; c < 3; c++) {
      const shift = 16 - 8 * c;
      const a = (stops[k] >> shift) & 255;
      const b = (stops[k + 1] >> shift) & 255;
      bytes[4 * i + c] = Math.round(a + (b - a) * f);
    }
    bytes[4 * i + 3] = 255;
  }
  return bytes;
}

export function colormapTexture(name) {
  const texture = new THREE.DataTexture(colormapBytes(name), 256, 1, THREE.RGBAFormat);
  texture.magFilter = THREE.LinearFilter;
  texture.minFilter = THREE.LinearFilter;
  texture.needsUpdate = true;
  return texture;
}

export function formatValue(x) {
  if (!Number.isFinite(x)) return String(x);
  const a = Math.abs(x);
  if (a !== 0 && (a < 1e-3 || a >= 1e5)) return x.toExponential(3);
  return x.toPrecision(4).replace(/(\.\d*?)0+$/, '$1').replace(/\.$/, '');
}

// Horizontal bar with min, middle and max labels.
export function drawColorbar(canvas, name, min, max, unit) {
  const ctx = canvas.getContext('2d');
  const w = canvas.width, h = canvas.height, barH = Math.round(h * 0.45);
  const bytes = colormapBytes(name);
  ctx.clearRect(0, 0, w, h);
  for (let x = 0; x < w; x++) {
    const i = Math.round((x / (w - 1)) * 255);
    ctx.fillStyle = `rgb(${bytes[4 * i]},${bytes[4 * i + 1]},${bytes[4 * i + 2]})`;
    ctx.fillRect(x, 0, 1, barH);
  }
  ctx.fillStyle = '#ddd';
  ctx.font = `${Math.round(h * 0.38)}px sans-serif`;
  ctx.textBaseline = 'top';
  const u = unit ? ' ' + unit : '';
  ctx.textAlign = 'left';
  ctx.fillText(formatValue(min) + u, 0, barH + 2);
  ctx.textAlign = 'center';
  ctx.fillText(formatValue((min + max) / 2), w / 2, barH + 2);
  ctx.textAlign = 'right';
  ctx.fillText(formatValue(max) + u, w, barH + 2);
}
