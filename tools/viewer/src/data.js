// Reads the data the C++ writer embedded in the page: one JSON <script> with the metadata and
// one base64 <script> per binary buffer (little-endian typed arrays).

const TYPES = { f32: Float32Array, u32: Uint32Array, u16: Uint16Array };

async function decodeBase64(text) {
  // The native decoder where there is one (Chrome 140+, Firefox 133+, Safari 18.2+); else fetch()
  // on a data: URL, which also decodes natively and works offline from file://; else atob.
  if (typeof Uint8Array.fromBase64 === 'function') return Uint8Array.fromBase64(text).buffer;
  try {
    const response = await fetch('data:application/octet-stream;base64,' + text);
    return await response.arrayBuffer();
  } catch (err) {
    const binary = atob(text);
    const bytes = new Uint8Array(binary.length);
    for (let i = 0; i < binary.length; i++) bytes[i] = binary.charCodeAt(i);
    return bytes.buffer;
  }
}

async function readBuffer(name, type) {
  const element = document.getElementById('vessel-buffer-' + name);
  if (!element) throw new Error(`the page has no data buffer '${name}'; regenerate it`);
  const buffer = await decodeBase64(element.textContent.trim());
  return new TYPES[type](buffer);
}

// Returns { meta, positions, normals, uv, indices, seam, fields: [{..meta, values: Uint16Array}] }.
export async function loadData() {
  const meta = JSON.parse(document.getElementById('vessel-meta').textContent);
  const [positions, normals, uv, indices, seam] = await Promise.all([
    readBuffer('positions', 'f32'),
    readBuffer('normals', 'f32'),
    readBuffer('uv', 'f32'),
    readBuffer('indices', 'u32'),
    readBuffer('seam', 'f32'),
  ]);
  const fields = [];
  for (let i = 0; i < meta.fields.length; i++) {
    fields.push({ ...meta.fields[i], values: await readBuffer('field' + i, 'u16') });
  }
  return { meta, positions, normals, uv, indices, seam, fields };
}
