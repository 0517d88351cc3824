// Point location in the flattened map: a uniform grid of triangle lists (CSR arrays), built once.
// A map point gives its triangle and barycentric coordinates, from which the same wall point in
// 3D and the field value follow.

export class MapLocator {
  constructor(uv, indices) {
    this.uv = uv;
    this.indices = indices;
    const nf = indices.length / 3;
    let minU = Infinity, minV = Infinity, maxU = -Infinity, maxV = -Infinity;
    for (let i = 0; i < uv.length; i += 2) {
      minU = Math.min(minU, uv[i]); maxU = Math.max(maxU, uv[i]);
      minV = Math.min(minV, uv[i + 1]); maxV = Math.max(maxV, uv[i + 1]);
    }
    this.min = [minU, minV];
    this.size = [Math.max(maxU - minU, 1e-30), Math.max(maxV - minV, 1e-30)];
    const n = Math.max(1, Math.ceil(Math.sqrt(nf / 2)));
    this.n = n;
    const start = new Uint32Array(n * n + 1);
    const span = (f) => {
      let u0 = Infinity, v0 = Infinity, u1 = -Infinity, v1 = -Infinity;
      for (let c = 0; c < 3; c++) {
        const k = indices[3 * f + c];
        u0 = Math.min(u0, uv[2 * k]); u1 = Math.max(u1, uv[2 * k]);
        v0 = Math.min(v0, uv[2 * k + 1]); v1 = Math.max(v1, uv[2 * k + 1]);
      }
      return [this.cell(0, u0), this.cell(0, u1), this.cell(1, v0), this.cell(1, v1)];
    };
    for (let f = 0; f < nf; f++) {
      const [i0, i1, j0, j1] = span(f);
      for (let j = j0; j <= j1; j++) for (let i = i0; i <= i1; i++) start[j * n + i + 1]++;
    }
    for (let c = 0; c < n * n; c++) start[c + 1] += start[c];
    const fill = start.slice(0, n * n);
    const faces = new Uint32Array(start[n * n]);
    for (let f = 0; f < nf; f++) {
      const [i0, i1, j0, j1] = span(f);
      for (let j = j0; j <= j1; j++) for (let i = i0; i <= i1; i++) faces[fill[j * n + i]++] = f;
    }
    this.start = start;
    this.faces = faces;
  }

  cell(axis, x) {
    const c = Math.floor(((x - this.min[axis]) / this.size[axis]) * this.n);
    return Math.min(this.n - 1, Math.max(0, c));
  }

  // Barycentric coordinates of (u, v) in face f.
  barycentric(f, u, v) {
    const { uv, indices } = this;
    const a = indices[3 * f], b = indices[3 * f + 1], c = indices[3 * f + 2];
    const x0 = uv[2 * a], y0 = uv[2 * a + 1];
    const x1 = uv[2 * b] - x0, y1 = uv[2 * b + 1] - y0;
    const x2 = uv[2 * c] - x0, y2 = uv[2 * c + 1] - y0;
    const px = u - x0, py = v - y0;
    const det = x1 * y2 - x2 * y1;
    if (det === 0) return null;
    const l1 = (px * y2 - x2 * py) / det;
    const l2 = (x1 * py - px * y1) / det;
    return [1 - l1 - l2, l1, l2];
  }

  // { face, bary } of the triangle containing (u, v); within `slack` cells, the nearest
  // triangle also counts (the 3D pick is quantized). null when the point is off the map.
  locate(u, v, slack = 0) {
    const ci = this.cell(0, u), cj = this.cell(1, v);
    let best = null, bestScore = -Infinity;
    for (let j = Math.max(0, cj - slack); j <= Math.min(this.n - 1, cj + slack); j++) {
      for (let i = Math.max(0, ci - slack); i <= Math.min(this.n - 1, ci + slack); i++) {
        const c = j * this.n + i;
        for (let k = this.start[c]; k < this.start[c + 1]; k++) {
          const f = this.faces[k];
          const bary = this.barycentric(f, u, v);
          if (!bary) continue;
          const score = Math.min(bary[0], bary[1], bary[2]);
          if (score >= 0) return { face: f, bary };
          if (score > bestScore) { bestScore = score; best = { face: f, bary }; }
        }
      }
    }
    if (slack === 0 || !best || bestScore < -0.5) return null;
    const clamped = best.bary.map((x) => Math.max(0, x));
    const sum = clamped[0] + clamped[1] + clamped[2];
    return { face: best.face, bary: clamped.map((x) => x / sum) };
  }
}
