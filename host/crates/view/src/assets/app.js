// ger view: the page. Hand-written, no framework and no build step, so the
// binary can embed it as is. The server's side of the conversation is
// host/docs/view-api.md; this file only reads what that contract promises.
//
// Sections: helpers · matrices · virtual list · editor · 3D view · the app
// (snapshots, selection, editing, live updates, keys).

// ───────────────────────────── helpers ─────────────────────────────

/** One text line, in CSS pixels: the same number as `--lh` in style.css. */
const LH = 18;
/** Browsers cap an element's height (~33M px in Chromium); lists taller than
 *  this are scrolled proportionally instead of pixel for pixel. */
const MAX_SCROLL_PX = 8_000_000;
/** A click picks the piece nearest the pointer within this many CSS pixels. */
const PICK_PX = 6;
/** Keystrokes are sent together once typing pauses this long. */
const DEBOUNCE_MS = 150;

const $ = (id) => document.getElementById(id);

function el(tag, className, text) {
  const e = document.createElement(tag);
  if (className) e.className = className;
  if (text !== undefined) e.textContent = text;
  return e;
}

/** Lines of a text; a final newline does not start another line. */
function splitLines(text) {
  const lines = text.split('\n');
  if (lines.length > 1 && lines[lines.length - 1] === '') lines.pop();
  return lines;
}

class HttpError extends Error {
  constructor(status, message) {
    super(message);
    this.status = status;
  }
}

async function request(url, options = {}) {
  const response = await fetch(url, { cache: 'no-store', ...options });
  if (!response.ok) {
    let message = `${response.status} ${response.statusText}`;
    try {
      const body = await response.json();
      if (body && body.error) message = body.error;
    } catch {
      // Not JSON: keep the status line.
    }
    throw new HttpError(response.status, message);
  }
  return response;
}

const getJSON = async (url) => (await request(url)).json();
const getBinary = async (url) => (await request(url)).arrayBuffer();
const post = async (url, body) => (await request(url, { method: 'POST', body })).json();

// ───────────────────────────── matrices ─────────────────────────────
// Column-major 4×4, as WebGL wants them.

const mat4 = {
  identity: () => new Float32Array([1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]),
  multiply(a, b) {
    const out = new Float32Array(16);
    for (let c = 0; c < 4; c++) {
      for (let r = 0; r < 4; r++) {
        let s = 0;
        for (let k = 0; k < 4; k++) s += a[k * 4 + r] * b[c * 4 + k];
        out[c * 4 + r] = s;
      }
    }
    return out;
  },
  translate(x, y, z) {
    const m = mat4.identity();
    m[12] = x;
    m[13] = y;
    m[14] = z;
    return m;
  },
  rotateX(a) {
    const c = Math.cos(a), s = Math.sin(a);
    return new Float32Array([1, 0, 0, 0, 0, c, s, 0, 0, -s, c, 0, 0, 0, 0, 1]);
  },
  rotateZ(a) {
    const c = Math.cos(a), s = Math.sin(a);
    return new Float32Array([c, s, 0, 0, -s, c, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]);
  },
  perspective(fovy, aspect, near, far) {
    const f = 1 / Math.tan(fovy / 2), nf = 1 / (near - far);
    return new Float32Array([f / aspect, 0, 0, 0, 0, f, 0, 0, 0, 0, (far + near) * nf, -1, 0, 0, 2 * far * near * nf, 0]);
  },
  ortho(halfW, halfH, near, far) {
    const nf = 1 / (near - far);
    return new Float32Array([1 / halfW, 0, 0, 0, 0, 1 / halfH, 0, 0, 0, 0, 2 * nf, 0, 0, 0, (far + near) * nf, 1]);
  },
};

// ───────────────────────────── virtual list ─────────────────────────────

/** A scrolling list of `count` rows of LH pixels where only the rows in
 *  sight exist in the DOM, so a million lines scroll as smoothly as ten. */
class VirtualList {
  constructor(root, renderRow, onPick) {
    this.root = root;
    this.renderRow = renderRow;
    this.count = 0;
    this.spacer = el('div', 'spacer');
    this.rows = el('div', 'rows');
    root.append(this.spacer, this.rows);
    this.frame = 0;
    root.addEventListener('scroll', () => this.schedule());
    new ResizeObserver(() => this.schedule()).observe(root);
    root.addEventListener('click', (event) => {
      const row = event.target.closest('.vrow');
      if (row) onPick(Number(row.dataset.i), event);
    });
  }

  setCount(count) {
    this.count = count;
    this.spacer.style.height = `${Math.min(count * LH, MAX_SCROLL_PX)}px`;
    this.render();
  }

  schedule() {
    if (!this.frame) {
      this.frame = requestAnimationFrame(() => {
        this.frame = 0;
        this.render();
      });
    }
  }

  /** The first row in sight and where (in content pixels) it goes. */
  window() {
    const height = this.root.clientHeight, top = this.root.scrollTop;
    const shown = Math.ceil(height / LH) + 1;
    if (this.count * LH <= MAX_SCROLL_PX) {
      const first = Math.floor(top / LH);
      return { first, offset: first * LH, shown };
    }
    const ratio = top / Math.max(1, MAX_SCROLL_PX - height);
    const first = Math.floor(ratio * Math.max(0, this.count - shown + 2));
    return { first, offset: top, shown };
  }

  render() {
    const { first, offset, shown } = this.window();
    const last = Math.min(this.count, first + shown);
    const fragment = document.createDocumentFragment();
    for (let i = first; i < last; i++) {
      const row = this.renderRow(i);
      row.classList.add('vrow');
      row.dataset.i = i;
      fragment.append(row);
    }
    this.rows.replaceChildren(fragment);
    this.rows.style.transform = `translateY(${offset}px)`;
  }

  /** Scrolls row `i` into sight (centred) unless it already is. */
  reveal(i) {
    const height = this.root.clientHeight;
    const { first, shown } = this.window();
    if (i > first && i < first + shown - 2) return;
    if (this.count * LH <= MAX_SCROLL_PX) {
      this.root.scrollTop = i * LH - height / 2;
    } else {
      const span = Math.max(1, this.count - Math.ceil(height / LH) - 1);
      this.root.scrollTop = (Math.max(0, i - height / LH / 2) / span) * (MAX_SCROLL_PX - height);
    }
    this.render();
  }
}

// ───────────────────────────── editor ─────────────────────────────

/** The program text: a plain textarea (the browser does the editing), with a
 *  gutter of line numbers and diagnostic marks, and a backdrop under the
 *  transparent textarea that draws the selected line and squiggles. Gutter
 *  and backdrop hold only the lines in sight. */
class Editor {
  constructor(root, { onInput, onCursor, onLine }) {
    this.textarea = root.querySelector('textarea');
    this.gutter = root.querySelector('.gutter');
    this.backdrop = root.querySelector('.backdrop');
    this.diagnostics = new Map(); // line → [diagnostic]
    this.selected = 0;
    this.lines = [''];
    this.frame = 0;
    this.textarea.addEventListener('input', () => {
      this.lines = splitLines(this.textarea.value);
      this.render();
      onInput();
    });
    this.textarea.addEventListener('scroll', () => this.schedule());
    new ResizeObserver(() => this.schedule()).observe(root);
    // The caret's line is the selection; read it after the browser moved it.
    const cursor = () => onCursor(this.caretLine());
    this.textarea.addEventListener('click', cursor);
    this.textarea.addEventListener('keyup', (event) => {
      if (event.key.startsWith('Arrow') || event.key.startsWith('Page') || event.key === 'Home' || event.key === 'End') {
        cursor();
      }
    });
    this.gutter.addEventListener('click', (event) => {
      const row = event.target.closest('[data-line]');
      if (row) onLine(Number(row.dataset.line));
    });
  }

  get text() {
    return this.textarea.value;
  }

  /** Replaces the text, keeping the caret and scroll where they were. */
  setText(text) {
    const { selectionStart, selectionEnd, scrollTop, scrollLeft } = this.textarea;
    this.textarea.value = text;
    this.textarea.setSelectionRange(selectionStart, selectionEnd);
    this.textarea.scrollTop = scrollTop;
    this.textarea.scrollLeft = scrollLeft;
    this.lines = splitLines(this.textarea.value);
    this.render();
  }

  setReadOnly(readOnly) {
    this.textarea.readOnly = readOnly;
  }

  caretLine() {
    const value = this.textarea.value, end = this.textarea.selectionStart;
    let line = 1;
    for (let i = value.indexOf('\n'); i !== -1 && i < end; i = value.indexOf('\n', i + 1)) line++;
    return line;
  }

  setDiagnostics(byLine) {
    this.diagnostics = byLine;
    this.render();
  }

  select(line) {
    this.selected = line;
    this.render();
  }

  /** Scrolls 1-based `line` into sight (centred) unless it already is. */
  reveal(line) {
    const t = this.textarea, top = (line - 1) * LH;
    if (top < t.scrollTop || top + LH > t.scrollTop + t.clientHeight) {
      t.scrollTop = top - t.clientHeight / 2;
    }
    this.render();
  }

  /** Puts the caret at the start of `line` and scrolls to it. */
  focusLine(line) {
    let offset = 0;
    for (let i = 1; i < line && i <= this.lines.length; i++) offset += this.lines[i - 1].length + 1;
    this.textarea.focus({ preventScroll: true });
    this.textarea.setSelectionRange(offset, offset);
    this.reveal(line);
  }

  schedule() {
    if (!this.frame) {
      this.frame = requestAnimationFrame(() => {
        this.frame = 0;
        this.render();
      });
    }
  }

  render() {
    const { scrollTop, scrollLeft, clientHeight } = this.textarea;
    const first = Math.max(1, Math.floor(scrollTop / LH) + 1);
    const last = Math.min(this.lines.length, first + Math.ceil(clientHeight / LH) + 1);
    const gutter = document.createDocumentFragment(), back = document.createDocumentFragment();
    for (let line = first; line <= last; line++) {
      const top = `${(line - 1) * LH - scrollTop}px`;
      const number = el('div', line === this.selected ? 'sel' : '', String(line));
      number.dataset.line = line;
      number.style.top = top;
      const diags = this.diagnostics.get(line);
      if (diags) {
        number.classList.add(worst(diags));
        number.title = diags.map((d) => `${d.severity}: ${d.message}`).join('\n');
        number.prepend(el('span', 'mark', worst(diags) === 'error' ? '✖' : '▲'));
        for (const d of diags) {
          const text = this.lines[line - 1] ?? '';
          const start = Math.max(1, d.column || 1);
          const end = d.end_line === line && d.end_column > start ? d.end_column : Math.max(text.length + 1, start + 1);
          const squiggle = el('div', `squiggle ${d.severity}`);
          squiggle.style.top = top;
          squiggle.style.left = `calc(${6 - scrollLeft}px + ${start - 1}ch)`;
          squiggle.style.width = `${end - start}ch`;
          back.append(squiggle);
        }
      }
      if (line === this.selected) {
        const hl = el('div', 'hl');
        hl.dataset.line = line;
        hl.style.top = top;
        back.prepend(hl);
      }
      gutter.append(number);
    }
    this.gutter.replaceChildren(gutter);
    this.backdrop.replaceChildren(back);
  }
}

const SEVERITY_RANK = { error: 3, warning: 2, note: 1, help: 0 };

function worst(diags) {
  return diags.reduce((w, d) => ((SEVERITY_RANK[d.severity] ?? 1) > (SEVERITY_RANK[w] ?? 1) ? d.severity : w), 'help');
}

// ───────────────────────────── 3D view ─────────────────────────────

/** Bytes in one toolpath record of /api/path: six f32, line, kind. */
const RECORD = 32;
const KIND_COLOURS = [
  [0.9, 0.27, 0.27, 0.8], // 0 rapid: red
  [0.24, 0.48, 1.0, 1.0], // 1 feed: blue
  [0.13, 0.78, 0.9, 1.0], // 2 arc: cyan-blue
  [0.55, 0.58, 0.64, 0.6], // 3 the stock's outline (drawn by the page, not sent)
  [0.47, 0.85, 0.35, 1.0], // 4 the fixtures' edges (the snapshot's `fixtures`): green, as in `ger render`
];
/** The selection. The end-to-end test looks for this colour in the canvas. */
const HIGHLIGHT = [1.0, 0.69, 0.0, 1.0];
const BACKGROUND = [0.106, 0.118, 0.137, 1];
const FOV = (40 * Math.PI) / 180;
/** Above this many height cells the page draws a coarser grid (each vertex the
 *  lowest cell of its block, so narrow cuts stay visible). */
const MAX_GRID = 1 << 20;

const MESH_VS = `#version 300 es
precision highp float;
precision highp int;
precision highp sampler2D;
uniform sampler2D u_heights;
uniform highp usampler2D u_verdicts;
uniform bool u_heat;
uniform ivec2 u_n;
uniform vec2 u_origin, u_step;
uniform mat4 u_mvp;
out vec3 v_normal;
out float v_z;
flat out uint v_verdict;
float h(ivec2 c) { return texelFetch(u_heights, clamp(c, ivec2(0), u_n - 1), 0).r; }
void main() {
  // No vertex buffer: the vertex's cell comes from its index, its height from
  // the texture, so a new snapshot only re-uploads the heights.
  ivec2 c = ivec2(gl_VertexID % u_n.x, gl_VertexID / u_n.x);
  float z = h(c);
  float dx = (h(c + ivec2(1, 0)) - h(c - ivec2(1, 0))) / (2.0 * u_step.x);
  float dy = (h(c + ivec2(0, 1)) - h(c - ivec2(0, 1))) / (2.0 * u_step.y);
  v_normal = normalize(vec3(-dx, -dy, 1.0));
  v_z = z;
  v_verdict = u_heat ? texelFetch(u_verdicts, c, 0).r : 0u;
  gl_Position = u_mvp * vec4(u_origin + vec2(c) * u_step, z, 1.0);
}`;

const MESH_FS = `#version 300 es
precision highp float;
uniform float u_top, u_bottom, u_eps;
uniform vec3 u_light;
uniform bool u_heat;
in vec3 v_normal;
in float v_z;
flat in uint v_verdict;
out vec4 colour;
// The design layer's colours, as ger compare's heat map: unjudged, within, gouged, material left.
const vec3 VERDICT[4] = vec3[4](vec3(0.88), vec3(0.27, 0.67, 0.31), vec3(0.84, 0.16, 0.14), vec3(0.16, 0.35, 0.82));
void main() {
  float depth = u_top - v_z;
  float t = clamp(depth / max(u_top - u_bottom, 1e-6), 0.0, 1.0);
  vec3 stock = vec3(0.74, 0.73, 0.70);
  vec3 cut = mix(vec3(0.55, 0.80, 0.78), vec3(0.22, 0.28, 0.68), t);
  vec3 base = u_heat ? VERDICT[min(v_verdict, 3u)] : depth > u_eps ? cut : stock;
  float light = abs(dot(normalize(v_normal), u_light));
  colour = vec4(base * (0.35 + 0.65 * light), 1.0);
}`;

const LINES_VS = `#version 300 es
precision highp float;
in vec4 a_point; // x, y, z, kind
in float a_along; // 0 at a piece's start, its length at its end
uniform mat4 u_mvp;
flat out uint v_kind;
out float v_along;
void main() {
  v_kind = uint(a_point.w);
  v_along = a_along;
  gl_Position = u_mvp * vec4(a_point.xyz, 1.0);
}`;

const LINES_FS = `#version 300 es
precision highp float;
uniform vec4 u_colours[5];
uniform float u_dash;
flat in uint v_kind;
in float v_along;
out vec4 colour;
void main() {
  // Rapids dashed, so they read as rapids without their colour too.
  if (v_kind == 0u && fract(v_along / u_dash) > 0.6) discard;
  colour = u_colours[min(v_kind, 4u)];
}`;

const THICK_VS = `#version 300 es
precision highp float;
in vec3 a_p0;
in vec3 a_p1;
in float a_corner;
uniform mat4 u_mvp;
uniform vec2 u_viewport;
uniform float u_width;
void main() {
  // WebGL draws lines one pixel wide, so a selected piece is a quad of six
  // vertices widened in screen space (and lengthened, to square its ends).
  int id = int(a_corner);
  float end = (id == 2 || id == 4 || id == 5) ? 1.0 : 0.0;
  float side = (id == 1 || id == 2 || id == 4) ? 1.0 : -1.0;
  vec4 c0 = u_mvp * vec4(a_p0, 1.0), c1 = u_mvp * vec4(a_p1, 1.0);
  vec2 half_vp = u_viewport * 0.5;
  vec2 d = c1.xy / c1.w * half_vp - c0.xy / c0.w * half_vp;
  d = length(d) < 1e-4 ? vec2(1.0, 0.0) : normalize(d);
  vec2 offset = (vec2(-d.y, d.x) * side + d * (end * 2.0 - 1.0)) * u_width * 0.5;
  vec4 c = end > 0.5 ? c1 : c0;
  c.xy += offset / half_vp * c.w;
  gl_Position = c;
}`;

const THICK_FS = `#version 300 es
precision highp float;
uniform vec4 u_colour;
out vec4 colour;
void main() { colour = u_colour; }`;

function compile(gl, vsText, fsText) {
  const shader = (type, text) => {
    const s = gl.createShader(type);
    gl.shaderSource(s, text);
    gl.compileShader(s);
    if (!gl.getShaderParameter(s, gl.COMPILE_STATUS)) throw new Error(gl.getShaderInfoLog(s));
    return s;
  };
  const program = gl.createProgram();
  gl.attachShader(program, shader(gl.VERTEX_SHADER, vsText));
  gl.attachShader(program, shader(gl.FRAGMENT_SHADER, fsText));
  gl.linkProgram(program);
  if (!gl.getProgramParameter(program, gl.LINK_STATUS)) throw new Error(gl.getProgramInfoLog(program));
  const uniforms = {};
  const count = gl.getProgramParameter(program, gl.ACTIVE_UNIFORMS);
  for (let i = 0; i < count; i++) {
    const name = gl.getActiveUniform(program, i).name.replace(/\[0\]$/, '');
    uniforms[name] = gl.getUniformLocation(program, name);
  }
  return { program, uniforms, attrib: (name) => gl.getAttribLocation(program, name) };
}

/** The part as a lit height field, the toolpath as lines, the selection as
 *  thick lines on top; an orbit camera; picking by projecting pieces. */
class Viewer {
  constructor(canvas, onPick) {
    this.canvas = canvas;
    this.onPick = onPick;
    // preserveDrawingBuffer: the page is redrawn only on change, and the
    // canvas's pixels must stay readable (screenshots, the browser test).
    const gl = canvas.getContext('webgl2', { antialias: true, preserveDrawingBuffer: true });
    if (!gl) throw new Error('no WebGL2');
    this.gl = gl;
    this.mesh = compile(gl, MESH_VS, MESH_FS);
    this.lines = compile(gl, LINES_VS, LINES_FS);
    this.thick = compile(gl, THICK_VS, THICK_FS);
    this.meshVao = gl.createVertexArray();
    this.heightTexture = gl.createTexture();
    this.verdictTexture = gl.createTexture();
    this.verdicts = false; // a design layer to show
    this.heat = false; // showing it
    this.gridIndices = gl.createBuffer();
    this.grid = null; // { gx, gy, count, origin, step, top, bottom }
    this.path = this.vertexSet(this.lines, [['a_point', 4], ['a_along', 1]]);
    this.outline = this.vertexSet(this.lines, [['a_point', 4], ['a_along', 1]]);
    this.fixtures = this.vertexSet(this.lines, [['a_point', 4], ['a_along', 1]]);
    this.selection = this.vertexSet(this.thick, [['a_p0', 3], ['a_p1', 3], ['a_corner', 1]]);
    this.records = null; // the toolpath, for picking and selection
    this.bounds = null;
    this.camera = { yaw: -0.5, pitch: 0.6, roll: 0, dist: 100, target: [0, 0, 0] };
    this.top2d = false;
    this.saved3d = null;
    this.frame = 0;
    this.afterDraw = [];
    this.listen();
    new ResizeObserver(() => this.resize()).observe(canvas);
    this.resize();
  }

  /** A vertex buffer and its layout: `attributes` as [name, floats]. Plain
   *  vertices, not instancing: SwiftShader (WebGL without a GPU, as in the
   *  browser test) draws a million instances very slowly. */
  vertexSet(shader, attributes) {
    const gl = this.gl;
    const vao = gl.createVertexArray(), buffer = gl.createBuffer();
    const stride = 4 * attributes.reduce((n, [, size]) => n + size, 0);
    gl.bindVertexArray(vao);
    gl.bindBuffer(gl.ARRAY_BUFFER, buffer);
    let offset = 0;
    for (const [name, size] of attributes) {
      const at = shader.attrib(name);
      gl.enableVertexAttribArray(at);
      gl.vertexAttribPointer(at, size, gl.FLOAT, false, stride, offset);
      offset += 4 * size;
    }
    gl.bindVertexArray(null);
    return { vao, buffer, stride, count: 0 };
  }

  upload(set, floats) {
    const gl = this.gl;
    gl.bindBuffer(gl.ARRAY_BUFFER, set.buffer);
    gl.bufferData(gl.ARRAY_BUFFER, floats, gl.STATIC_DRAW);
    set.count = floats.byteLength / set.stride;
  }

  /** Toolpath records (or the outline's) as line vertices: x, y, z, kind,
   *  distance along the piece. */
  lineVertices(records, words) {
    const n = records.length / 8, out = new Float32Array(n * 10);
    for (let i = 0; i < n; i++) {
      const r = i * 8, o = i * 10, kind = words[r + 7];
      out[o] = records[r];
      out[o + 1] = records[r + 1];
      out[o + 2] = records[r + 2];
      out[o + 3] = kind;
      out[o + 4] = 0;
      out[o + 5] = records[r + 3];
      out[o + 6] = records[r + 4];
      out[o + 7] = records[r + 5];
      out[o + 8] = kind;
      out[o + 9] = Math.hypot(records[r + 3] - records[r], records[r + 4] - records[r + 1], records[r + 5] - records[r + 2]);
    }
    return out;
  }

  /** `part` as /api/state gives it (or null), `heights` its Float32Array. */
  setPart(part, heights) {
    const gl = this.gl;
    if (!part || !heights) {
      this.grid = null;
      this.upload(this.outline, new Float32Array(0));
      this.requestDraw();
      return;
    }
    // A coarser grid for huge fields: each vertex the lowest of its block.
    const block = Math.max(1, Math.ceil(Math.sqrt((part.nx * part.ny) / MAX_GRID)));
    const gx = Math.ceil(part.nx / block), gy = Math.ceil(part.ny / block);
    let data = heights;
    if (block > 1) {
      data = new Float32Array(gx * gy).fill(Infinity);
      for (let y = 0; y < part.ny; y++) {
        const row = Math.floor(y / block) * gx;
        for (let x = 0; x < part.nx; x++) {
          const i = row + Math.floor(x / block), h = heights[y * part.nx + x];
          if (h < data[i]) data[i] = h;
        }
      }
    }
    gl.bindTexture(gl.TEXTURE_2D, this.heightTexture);
    gl.pixelStorei(gl.UNPACK_ALIGNMENT, 4);
    gl.texImage2D(gl.TEXTURE_2D, 0, gl.R32F, gx, gy, 0, gl.RED, gl.FLOAT, data);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MIN_FILTER, gl.NEAREST);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MAG_FILTER, gl.NEAREST);
    if (!this.grid || this.grid.gx !== gx || this.grid.gy !== gy) {
      // Two triangles per grid square; rebuilt only when the grid's size changes.
      const indices = new Uint32Array(6 * (gx - 1) * (gy - 1));
      let k = 0;
      for (let y = 0; y + 1 < gy; y++) {
        for (let x = 0; x + 1 < gx; x++) {
          const a = y * gx + x, b = a + 1, c = a + gx, d = c + 1;
          indices.set([a, b, d, a, d, c], k);
          k += 6;
        }
      }
      gl.bindVertexArray(this.meshVao);
      gl.bindBuffer(gl.ELEMENT_ARRAY_BUFFER, this.gridIndices);
      gl.bufferData(gl.ELEMENT_ARRAY_BUFFER, indices, gl.STATIC_DRAW);
      gl.bindVertexArray(null);
    }
    const stepX = part.cell_x * block, stepY = part.cell_y * block;
    this.grid = {
      gx,
      gy,
      count: 6 * (gx - 1) * (gy - 1),
      origin: [part.x0 + stepX / 2, part.y0 + stepY / 2],
      step: [stepX, stepY],
      top: part.top,
      bottom: part.bottom,
    };
    // The stock's box, drawn as twelve thin grey edges.
    const x1 = part.x0 + part.nx * part.cell_x, y1 = part.y0 + part.ny * part.cell_y;
    const corners = (z) => [
      [part.x0, part.y0, z],
      [x1, part.y0, z],
      [x1, y1, z],
      [part.x0, y1, z],
    ];
    const lo = corners(part.bottom), hi = corners(part.top);
    const edges = [];
    for (let i = 0; i < 4; i++) edges.push([lo[i], lo[(i + 1) % 4]], [hi[i], hi[(i + 1) % 4]], [lo[i], hi[i]]);
    const box = new ArrayBuffer(edges.length * RECORD);
    edges.forEach(([a, b], i) => {
      new Float32Array(box, i * RECORD, 6).set([...a, ...b]);
      new Uint32Array(box, i * RECORD + 24, 2).set([0, 3]);
    });
    this.upload(this.outline, this.lineVertices(new Float32Array(box), new Uint32Array(box)));
    this.partBox = { min: [part.x0, part.y0, part.bottom], max: [x1, y1, part.top] };
    this.requestDraw();
  }

  /** `fixtures` as /api/state gives them: each drawn by its edges (a
   *  cylinder's rims in 48 steps and four upright lines). */
  setFixtures(fixtures) {
    const edges = [];
    for (const f of fixtures || []) {
      const [x0, y0, z0] = f.min, [x1, y1, z1] = f.max;
      if (f.shape === 'cylinder') {
        const cx = (x0 + x1) / 2, cy = (y0 + y1) / 2, r = (x1 - x0) / 2, steps = 48;
        const at = (k, z) => [cx + r * Math.cos((2 * Math.PI * k) / steps), cy + r * Math.sin((2 * Math.PI * k) / steps), z];
        for (let k = 0; k < steps; k++) edges.push([at(k, z0), at(k + 1, z0)], [at(k, z1), at(k + 1, z1)]);
        for (let k = 0; k < steps; k += steps / 4) edges.push([at(k, z0), at(k, z1)]);
      } else {
        const corner = (i, z) => [i === 1 || i === 2 ? x1 : x0, i >= 2 ? y1 : y0, z];
        for (let i = 0; i < 4; i++) {
          edges.push([corner(i, z0), corner((i + 1) % 4, z0)], [corner(i, z1), corner((i + 1) % 4, z1)]);
          edges.push([corner(i, z0), corner(i, z1)]);
        }
      }
    }
    const records = new ArrayBuffer(edges.length * RECORD);
    edges.forEach(([a, b], i) => {
      new Float32Array(records, i * RECORD, 6).set([...a, ...b]);
      new Uint32Array(records, i * RECORD + 24, 2).set([0, 4]);
    });
    this.upload(this.fixtures, this.lineVertices(new Float32Array(records), new Uint32Array(records)));
    const all = fixtures || [];
    this.fixtureBox = all.length
      ? {
          min: [0, 1, 2].map((k) => Math.min(...all.map((f) => f.min[k]))),
          max: [0, 1, 2].map((k) => Math.max(...all.map((f) => f.max[k]))),
        }
      : null;
    this.requestDraw();
  }

  /** The design layer: /api/verdicts's bytes over `part`'s cells (or
   *  null), on the grid the heights are drawn on (of a block, the worst:
   *  gouged, then material left, then within). */
  setVerdicts(part, bytes) {
    const gl = this.gl;
    this.verdicts = Boolean(part && bytes && this.grid);
    if (!this.verdicts) {
      this.requestDraw();
      return;
    }
    const { gx, gy } = this.grid, block = Math.ceil(part.nx / gx) || 1;
    const RANK = [0, 1, 3, 2];
    let data = bytes;
    if (block > 1) {
      data = new Uint8Array(gx * gy);
      for (let y = 0; y < part.ny; y++) {
        const row = Math.floor(y / block) * gx;
        for (let x = 0; x < part.nx; x++) {
          const i = row + Math.floor(x / block), v = bytes[y * part.nx + x];
          if (RANK[v] > RANK[data[i]]) data[i] = v;
        }
      }
    }
    gl.bindTexture(gl.TEXTURE_2D, this.verdictTexture);
    gl.pixelStorei(gl.UNPACK_ALIGNMENT, 1);
    gl.texImage2D(gl.TEXTURE_2D, 0, gl.R8UI, gx, gy, 0, gl.RED_INTEGER, gl.UNSIGNED_BYTE, data);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MIN_FILTER, gl.NEAREST);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MAG_FILTER, gl.NEAREST);
    this.requestDraw();
  }

  setHeat(on) {
    this.heat = on;
    this.requestDraw();
  }

  /** `buffer` as /api/path gives it; `box` the path's {min, max}. */
  setPath(buffer, box) {
    this.records = buffer && buffer.byteLength ? new Float32Array(buffer) : null;
    this.recordWords = buffer && buffer.byteLength ? new Uint32Array(buffer) : null;
    this.upload(this.path, this.records ? this.lineVertices(this.records, this.recordWords) : new Float32Array(0));
    this.pathBox = box;
    this.requestDraw();
  }

  /** Thick-draws the pieces whose output line `wanted(line)` accepts. */
  setSelection(wanted) {
    const words = this.recordWords;
    const picked = [];
    if (words && wanted) {
      for (let i = 0, n = words.length / 8; i < n; i++) if (wanted(words[i * 8 + 6])) picked.push(i);
    }
    // Six vertices (two triangles) a piece, each with both ends and its corner.
    const out = new Float32Array(picked.length * 6 * 7), r = this.records;
    picked.forEach((piece, k) => {
      for (let corner = 0; corner < 6; corner++) {
        const v = (k * 6 + corner) * 7;
        out.set(r.subarray(piece * 8, piece * 8 + 6), v);
        out[v + 6] = corner;
      }
    });
    this.upload(this.selection, out);
    this.requestDraw();
    return picked.length;
  }

  /** The box of everything there is to see. */
  box() {
    const boxes = [this.partBox, this.pathBox, this.fixtureBox].filter((b) => b && b.min && b.max);
    if (!this.grid) boxes.splice(0, boxes.length, ...boxes.filter((b) => b !== this.partBox));
    if (!boxes.length) return null;
    const min = [0, 1, 2].map((k) => Math.min(...boxes.map((b) => b.min[k])));
    const max = [0, 1, 2].map((k) => Math.max(...boxes.map((b) => b.max[k])));
    return { min, max };
  }

  /** Centres the box of everything and backs off until its corners, seen
   *  from the current direction, all fit in the canvas. */
  fit() {
    const box = this.box();
    if (!box) return;
    const c = this.camera;
    c.target = [0, 1, 2].map((k) => (box.min[k] + box.max[k]) / 2);
    c.dist = 0;
    const view = this.viewMatrix(); // with dist 0: camera coordinates about the target
    const aspect = this.canvas.width / Math.max(1, this.canvas.height), tan = Math.tan(FOV / 2);
    let dist = 1e-3;
    for (let corner = 0; corner < 8; corner++) {
      const p = [0, 1, 2].map((k) => (corner >> k) & 1 ? box.max[k] : box.min[k]);
      const x = view[0] * p[0] + view[4] * p[1] + view[8] * p[2] + view[12];
      const y = view[1] * p[0] + view[5] * p[1] + view[9] * p[2] + view[13];
      const z = this.top2d ? 0 : view[2] * p[0] + view[6] * p[1] + view[10] * p[2] + view[14];
      // A corner at camera depth z needs the eye at least this far back.
      dist = Math.max(dist, z + Math.abs(x) / (tan * aspect), z + Math.abs(y) / tan);
    }
    c.dist = dist * 1.08;
    this.requestDraw();
  }

  setTop2d(on) {
    if (on === this.top2d) return;
    this.top2d = on;
    if (on) {
      this.saved3d = { yaw: this.camera.yaw, pitch: this.camera.pitch, roll: this.camera.roll };
      Object.assign(this.camera, { yaw: 0, pitch: Math.PI / 2, roll: 0 });
    } else if (this.saved3d) {
      Object.assign(this.camera, this.saved3d);
    }
    this.requestDraw();
  }

  // The manual's keys: J/L rotate left/right, I/M up/down, U/O twist, A/Z zoom.
  rotate(yaw, pitch, roll) {
    if (this.top2d) return;
    const c = this.camera;
    c.yaw += yaw;
    c.pitch = Math.max(-Math.PI / 2, Math.min(Math.PI / 2, c.pitch + pitch));
    c.roll += roll;
    this.requestDraw();
  }

  zoom(factor) {
    this.camera.dist = Math.max(1e-3, this.camera.dist * factor);
    this.requestDraw();
  }

  /** Moves the target by a drag of (dx, dy) CSS pixels. */
  pan(dx, dy) {
    const view = this.viewMatrix();
    const perPixel = (2 * this.camera.dist * Math.tan(FOV / 2)) / Math.max(1, this.canvas.clientHeight);
    for (let k = 0; k < 3; k++) {
      this.camera.target[k] += (-view[k * 4] * dx + view[k * 4 + 1] * dy) * perPixel;
    }
    this.requestDraw();
  }

  /** The box's diagonal, or the camera's distance when there is nothing. */
  size() {
    const box = this.box();
    return box ? Math.hypot(...[0, 1, 2].map((k) => box.max[k] - box.min[k])) : this.camera.dist;
  }

  viewMatrix() {
    const c = this.camera;
    // From above, the distance only scales the orthographic view; the eye
    // stays clear of the part so zooming in never clips it.
    const eye = this.top2d ? Math.max(c.dist, 2 * this.size()) : c.dist;
    let m = mat4.translate(0, 0, -eye);
    m = mat4.multiply(m, mat4.rotateZ(c.roll));
    m = mat4.multiply(m, mat4.rotateX(c.pitch - Math.PI / 2));
    m = mat4.multiply(m, mat4.rotateZ(-c.yaw));
    return mat4.multiply(m, mat4.translate(-c.target[0], -c.target[1], -c.target[2]));
  }

  mvp() {
    const c = this.camera, aspect = this.canvas.width / Math.max(1, this.canvas.height);
    const size = this.size();
    const halfH = c.dist * Math.tan(FOV / 2);
    const projection = this.top2d
      ? mat4.ortho(halfH * aspect, halfH, 1e-3, Math.max(c.dist, 2 * size) + 2 * size)
      : mat4.perspective(FOV, aspect, Math.max(c.dist * 0.01, c.dist - 2 * size), c.dist + 2 * size + 1);
    return mat4.multiply(projection, this.viewMatrix());
  }

  /** World point → CSS pixels in the canvas, and depth (null behind the eye). */
  project(p, m = this.mvp()) {
    const x = m[0] * p[0] + m[4] * p[1] + m[8] * p[2] + m[12];
    const y = m[1] * p[0] + m[5] * p[1] + m[9] * p[2] + m[13];
    const z = m[2] * p[0] + m[6] * p[1] + m[10] * p[2] + m[14];
    const w = m[3] * p[0] + m[7] * p[1] + m[11] * p[2] + m[15];
    if (w <= 0) return null;
    return [
      ((x / w + 1) / 2) * this.canvas.clientWidth,
      ((1 - y / w) / 2) * this.canvas.clientHeight,
      z / w,
    ];
  }

  /** The output line of the piece under (px, py), or -1. Of the pieces within
   *  PICK_PX on screen, the nearest the eye wins. */
  pick(px, py) {
    const r = this.records, words = this.recordWords;
    if (!r) return -1;
    const m = this.mvp(), w = this.canvas.clientWidth, h = this.canvas.clientHeight;
    // Inlined projection into `screen`, no allocation: a million pieces
    // are picked in tens of milliseconds.
    const screen = new Float64Array(3);
    const project = (i) => {
      const x = r[i], y = r[i + 1], z = r[i + 2];
      const cw = m[3] * x + m[7] * y + m[11] * z + m[15];
      if (cw <= 0) return false;
      screen[0] = ((((m[0] * x + m[4] * y + m[8] * z + m[12]) / cw) + 1) / 2) * w;
      screen[1] = ((1 - (m[1] * x + m[5] * y + m[9] * z + m[13]) / cw) / 2) * h;
      screen[2] = (m[2] * x + m[6] * y + m[10] * z + m[14]) / cw;
      return true;
    };
    let best = -1, bestDepth = Infinity;
    for (let i = 0, n = r.length / 8; i < n; i++) {
      if (!project(i * 8)) continue;
      const ax = screen[0], ay = screen[1], az = screen[2];
      if (!project(i * 8 + 3)) continue;
      const dx = screen[0] - ax, dy = screen[1] - ay, len2 = dx * dx + dy * dy;
      const t = len2 > 0 ? Math.max(0, Math.min(1, ((px - ax) * dx + (py - ay) * dy) / len2)) : 0;
      const ex = ax + t * dx - px, ey = ay + t * dy - py;
      if (ex * ex + ey * ey > PICK_PX * PICK_PX) continue;
      const depth = az + t * (screen[2] - az);
      if (depth < bestDepth) {
        bestDepth = depth;
        best = words[i * 8 + 6];
      }
    }
    return best;
  }

  listen() {
    const canvas = this.canvas;
    let drag = null;
    canvas.addEventListener('contextmenu', (e) => e.preventDefault());
    canvas.addEventListener('pointerdown', (e) => {
      canvas.setPointerCapture(e.pointerId);
      drag = { x: e.clientX, y: e.clientY, startX: e.clientX, startY: e.clientY, moved: false };
    });
    canvas.addEventListener('pointermove', (e) => {
      if (!drag) return;
      const dx = e.clientX - drag.x, dy = e.clientY - drag.y;
      drag.x = e.clientX;
      drag.y = e.clientY;
      if (Math.hypot(e.clientX - drag.startX, e.clientY - drag.startY) > 3) drag.moved = true;
      if (!drag.moved) return;
      canvas.classList.add('dragging');
      if (e.shiftKey || e.buttons & 2 || e.buttons & 4 || this.top2d) this.pan(dx, dy);
      else this.rotate(-dx * 0.01, dy * 0.01, 0);
    });
    canvas.addEventListener('pointerup', (e) => {
      canvas.classList.remove('dragging');
      if (drag && !drag.moved && e.button === 0) {
        const rect = canvas.getBoundingClientRect();
        this.onPick(this.pick(e.clientX - rect.left, e.clientY - rect.top));
      }
      drag = null;
    });
    canvas.addEventListener(
      'wheel',
      (e) => {
        e.preventDefault();
        this.zoom(Math.exp(e.deltaY * (e.deltaMode === 1 ? 0.05 : 0.0015)));
      },
      { passive: false },
    );
  }

  resize() {
    const dpr = window.devicePixelRatio || 1;
    const w = Math.max(1, Math.round(this.canvas.clientWidth * dpr));
    const h = Math.max(1, Math.round(this.canvas.clientHeight * dpr));
    if (w !== this.canvas.width || h !== this.canvas.height) {
      this.canvas.width = w;
      this.canvas.height = h;
    }
    this.requestDraw();
  }

  /** Draws on the next frame; `then` runs once that frame is drawn. */
  requestDraw(then) {
    if (then) this.afterDraw.push(then);
    if (!this.frame) {
      this.frame = requestAnimationFrame(() => {
        this.frame = 0;
        this.draw();
        for (const f of this.afterDraw.splice(0)) f();
      });
    }
  }

  draw() {
    const gl = this.gl;
    gl.viewport(0, 0, this.canvas.width, this.canvas.height);
    gl.clearColor(...BACKGROUND);
    gl.clear(gl.COLOR_BUFFER_BIT | gl.DEPTH_BUFFER_BIT);
    gl.enable(gl.DEPTH_TEST);
    gl.enable(gl.BLEND);
    gl.blendFunc(gl.SRC_ALPHA, gl.ONE_MINUS_SRC_ALPHA);
    const mvp = this.mvp();

    if (this.grid && this.grid.count) {
      const { program, uniforms: u } = this.mesh;
      gl.useProgram(program);
      gl.uniformMatrix4fv(u.u_mvp, false, mvp);
      gl.uniform2i(u.u_n, this.grid.gx, this.grid.gy);
      gl.uniform2fv(u.u_origin, this.grid.origin);
      gl.uniform2fv(u.u_step, this.grid.step);
      gl.uniform1f(u.u_top, this.grid.top);
      gl.uniform1f(u.u_bottom, this.grid.bottom);
      gl.uniform1f(u.u_eps, Math.max(1e-4, (this.grid.top - this.grid.bottom) * 1e-4));
      const light = [0.35, -0.55, 0.76], l = Math.hypot(...light);
      gl.uniform3fv(u.u_light, light.map((v) => v / l));
      gl.activeTexture(gl.TEXTURE0);
      gl.bindTexture(gl.TEXTURE_2D, this.heightTexture);
      gl.uniform1i(u.u_heights, 0);
      gl.activeTexture(gl.TEXTURE1);
      gl.bindTexture(gl.TEXTURE_2D, this.verdictTexture);
      gl.uniform1i(u.u_verdicts, 1);
      gl.uniform1i(u.u_heat, this.heat && this.verdicts ? 1 : 0);
      gl.activeTexture(gl.TEXTURE0);
      // The toolpath runs on the cut surface: push the surface back a little
      // so the lines in the bottom of a cut win the depth test.
      gl.enable(gl.POLYGON_OFFSET_FILL);
      gl.polygonOffset(1, 4);
      gl.bindVertexArray(this.meshVao);
      gl.drawElements(gl.TRIANGLES, this.grid.count, gl.UNSIGNED_INT, 0);
      gl.disable(gl.POLYGON_OFFSET_FILL);
    }

    const { program, uniforms: u } = this.lines;
    gl.useProgram(program);
    gl.uniformMatrix4fv(u.u_mvp, false, mvp);
    gl.uniform4fv(u.u_colours, KIND_COLOURS.flat());
    gl.uniform1f(u.u_dash, Math.max(1e-3, this.size() / 150));
    for (const set of [this.outline, this.fixtures, this.path]) {
      if (!set.count) continue;
      gl.bindVertexArray(set.vao);
      gl.drawArrays(gl.LINES, 0, set.count);
    }

    if (this.selection.count) {
      // The selection shows through the part: it is what the user asked to see.
      gl.disable(gl.DEPTH_TEST);
      const t = this.thick;
      gl.useProgram(t.program);
      gl.uniformMatrix4fv(t.uniforms.u_mvp, false, mvp);
      gl.uniform2f(t.uniforms.u_viewport, this.canvas.width, this.canvas.height);
      gl.uniform1f(t.uniforms.u_width, 4 * (window.devicePixelRatio || 1));
      gl.uniform4fv(t.uniforms.u_colour, HIGHLIGHT);
      gl.bindVertexArray(this.selection.vao);
      gl.drawArrays(gl.TRIANGLES, 0, this.selection.count);
    }
    gl.bindVertexArray(null);
  }
}

// ───────────────────────────── the app ─────────────────────────────

const app = {
  snapshot: null, // the last /api/state shown
  shown: 0, // its version
  output: [], // its output lines
  sourceOf: new Int32Array(0), // output line → source line
  sourceLines: null, // the program's lines, when read-only
  selection: null, // { out: i } or { src: line }
  // Local edits: the text in the editor is ahead of the server while a
  // debounced send is pending or in flight, or until the snapshot it asked
  // for (`awaited`) arrives. Until then snapshots must not overwrite it.
  editTimer: 0,
  sending: 0,
  awaited: 0,
  dirty: false,
  conflictKept: false,
  refit: true,
  file: null,
};

let viewer = null;
try {
  viewer = new Viewer($('view'), (line) => {
    if (line >= 0) select({ out: line }, { revealOutput: true, revealSource: true });
  });
} catch (error) {
  $('noGl').hidden = false;
  console.error(error);
}

const editor = new Editor($('editor'), {
  onInput: edited,
  onCursor: (line) => select({ src: line }, { revealOutput: true }),
  onLine: (line) => select({ src: line }, { revealOutput: true }),
});

const outputList = new VirtualList(
  $('output'),
  (i) => {
    const row = el('div');
    const src = app.sourceOf[i];
    const diags = src && editor.diagnostics.get(src);
    // The N numbers are already the program's lines (as the manual's
    // translator wrote them); the gutter numbers the output's own lines.
    row.append(el('span', `num ${diags ? worst(diags) : ''}`, String(i + 1)), el('span', 'text', app.output[i]));
    const sel = app.selection;
    if (sel && 'out' in sel && sel.out === i) row.classList.add('sel');
    else if (sel && src && src === selectedSource()) row.classList.add('related');
    return row;
  },
  (i) => select({ out: i }, { revealSource: true }),
);

const sourceList = new VirtualList(
  $('sourceList'),
  (i) => {
    const row = el('div');
    const diags = editor.diagnostics.get(i + 1);
    row.append(el('span', `num ${diags ? worst(diags) : ''}`, String(i + 1)), el('span', 'text', app.sourceLines[i]));
    if (diags) row.title = diags.map((d) => `${d.severity}: ${d.message}`).join('\n');
    if (selectedSource() === i + 1) row.classList.add('sel');
    return row;
  },
  (i) => select({ src: i + 1 }, { revealOutput: true }),
);

function selectedSource() {
  const sel = app.selection;
  if (!sel) return 0;
  return 'out' in sel ? app.sourceOf[sel.out] || 0 : sel.src;
}

/** Selects an output line or a source line, and shows it everywhere. */
function select(selection, { revealOutput = false, revealSource = false } = {}) {
  app.selection = selection;
  const src = selectedSource();
  editor.select(src);
  if (revealSource && src) {
    if (app.snapshot && app.snapshot.read_only) sourceList.reveal(src - 1);
    else editor.reveal(src);
  }
  sourceList.render();
  let pieces = 0;
  if (!selection) {
    if (viewer) viewer.setSelection(null);
  } else if ('out' in selection) {
    if (viewer) pieces = viewer.setSelection((line) => line === selection.out);
    if (revealOutput) outputList.reveal(selection.out);
  } else {
    if (viewer) pieces = viewer.setSelection((line) => app.sourceOf[line] === selection.src);
    if (revealOutput) {
      const first = app.sourceOf.indexOf(selection.src);
      if (first >= 0) outputList.reveal(first);
    }
  }
  outputList.render();
  const what = !selection
    ? ''
    : 'out' in selection
      ? `output line ${selection.out + 1}${src ? ` ← program line ${src}` : ''}`
      : `program line ${selection.src}`;
  $('selection').textContent = what && `${what}; ${pieces} piece${pieces === 1 ? '' : 's'}`;
  showRunTime(src);
}

/** "3 min 05 s", "1 h 02 min", "12.5 s", as `ger check` says a time. */
function duration(seconds) {
  const whole = Math.round(seconds);
  if (whole >= 3600) return `${Math.floor(whole / 3600)} h ${String(Math.floor((whole % 3600 + 30) / 60)).padStart(2, '0')} min`;
  if (whole >= 60) return `${Math.floor(whole / 60)} min ${String(whole % 60).padStart(2, '0')} s`;
  return `${seconds.toFixed(1)} s`;
}

/** The planned run time, and when the run reaches program line `src` (0: none selected). */
function showRunTime(src) {
  const run = app.snapshot && app.snapshot.run_time;
  const at = run && src ? run.lines[src - 1] : undefined;
  const total = run ? `${duration(run.seconds)} planned (${run.preset}${run.configured ? '' : ', no [machine.motion]'})` : '';
  $('runTime').textContent = at === undefined ? total : `reaches line ${src} at ${duration(at)} of ${total}`;
}

let messageTimer = 0;

/** A note in the status bar; errors stay until the next note, others fade. */
function message(text, isError = false) {
  const m = $('message');
  m.textContent = text;
  m.style.color = isError ? 'var(--error)' : '';
  clearTimeout(messageTimer);
  if (!isError) messageTimer = setTimeout(() => (m.textContent = ''), 3000);
}

// ── snapshots ──

let loading = null;
let loadAgain = false;

/** Fetches the latest snapshot and shows it. Calls while one is loading are
 *  folded into one more load afterwards. */
async function refresh() {
  if (loading) {
    loadAgain = true;
    return loading;
  }
  loading = (async () => {
    try {
      do {
        loadAgain = false;
        await loadLatest();
      } while (loadAgain);
    } catch (error) {
      message(`could not load: ${error.message}`, true);
    } finally {
      loading = null;
    }
  })();
  return loading;
}

async function loadLatest() {
  for (let attempt = 0; attempt < 8; attempt++) {
    const state = await getJSON('/api/state');
    showBusy(state.busy);
    if (state.version <= app.shown) return;
    const v = state.version;
    try {
      const [heights, path, verdicts] = await Promise.all([
        state.part ? getBinary(`/api/heights?version=${v}`) : null,
        state.path && state.path.pieces ? getBinary(`/api/path?version=${v}`) : null,
        state.part && state.design ? getBinary(`/api/verdicts?version=${v}`) : null,
      ]);
      show(state, heights && new Float32Array(heights), path, verdicts && new Uint8Array(verdicts));
      return;
    } catch (error) {
      // 410: a newer snapshot replaced this one while we fetched; take that.
      if (!(error instanceof HttpError && error.status === 410)) throw error;
    }
  }
}

function show(state, heights, path, verdicts) {
  const fileChanged = state.file !== app.file;
  app.snapshot = state;
  app.shown = state.version;
  app.file = state.file;
  if (fileChanged) {
    app.selection = null;
    app.refit = true;
    loadFiles();
  }

  // Output.
  app.output = splitLines(state.output.text);
  app.sourceOf = Int32Array.from(state.output.source_lines);
  $('outCount').textContent = `${app.output.length.toLocaleString()} lines`;
  outputList.setCount(app.output.length);

  // Diagnostics, by line for the editor and as a list.
  const byLine = new Map();
  for (const d of state.diagnostics) {
    if (!d.line) continue;
    if (!byLine.has(d.line)) byLine.set(d.line, []);
    byLine.get(d.line).push(d);
  }
  editor.setDiagnostics(byLine);
  showDiagnostics(state.diagnostics);

  // Source: the editor, or a read-only list for huge programs.
  const readOnly = !!state.read_only;
  $('editor').hidden = readOnly;
  $('sourceList').hidden = !readOnly;
  $('readOnly').hidden = !readOnly;
  editor.setReadOnly(readOnly);
  $('fileName').textContent = state.file;
  if (readOnly) {
    app.sourceLines = splitLines(state.source);
    sourceList.setCount(app.sourceLines.length);
  } else {
    app.sourceLines = null;
    const text = state.source.replace(/\r\n?/g, '\n');
    const ahead = app.editTimer || app.sending || state.version < app.awaited;
    if (!ahead && text !== editor.text) editor.setText(text);
    if (!ahead) app.dirty = false;
  }
  showSaved();

  // Keep the selection if its line is still there.
  const sel = app.selection;
  if (sel && 'out' in sel && sel.out >= app.output.length) app.selection = null;
  if (sel && 'src' in sel && sel.src > (app.sourceLines || editor.lines).length) app.selection = null;

  $('version').textContent = `v${state.version}`;
  $('elapsed').textContent = `${state.elapsed_ms} ms`;
  const p = state.path || { pieces: 0, total: 0 };
  // The design layer's button, with the comparison's figures.
  const d = state.design;
  $('heat').hidden = !d;
  if (d) {
    const unit = state.part?.units || '';
    const figure = (what, dev) => (dev.area ? `${what} ${dev.worst.toFixed(3)} ${unit} at worst over ${dev.area.toFixed(1)} ${unit}²` : `nothing ${what}`);
    $('heat').title = `${d.file}, tolerance ${d.tolerance} ${unit}: ${figure('gouged', d.gouge)}, ${figure('left', d.left)} (D)`;
  } else if (viewer?.heat) {
    setHeat(false);
  }
  $('pieces').textContent = p.decimated
    ? `${p.pieces.toLocaleString()} of ${p.total.toLocaleString()} pieces drawn (decimated)`
    : `${p.pieces.toLocaleString()} pieces`;

  if (viewer) {
    viewer.setPart(state.part, heights);
    viewer.setVerdicts(state.part, verdicts);
    viewer.setFixtures(state.fixtures);
    viewer.setPath(path, state.path);
    if (app.refit) {
      viewer.fit();
      app.refit = false;
    }
  }
  select(app.selection);
  // The browser test and the bench wait on this: the version whose text,
  // output and 3D view are all on screen.
  const markShown = () => {
    document.body.dataset.shown = String(state.version);
  };
  if (viewer) viewer.requestDraw(markShown);
  else requestAnimationFrame(markShown);
}

function showDiagnostics(diagnostics) {
  const list = $('diagnostics');
  $('diagCount').textContent = diagnostics.length ? `(${diagnostics.length})` : '';
  if (!diagnostics.length) {
    list.replaceChildren(el('li', 'none', 'No problems found.'));
    return;
  }
  // Thousands of diagnostics would only slow the page; the first ones matter.
  const items = diagnostics.slice(0, 1000).map((d) => {
    const li = el('li', d.severity);
    li.append(
      el('span', 'where', d.line ? `${d.line}:${d.column || 1}` : '—'),
      el('span', 'severity', d.severity),
      el('span', 'message', d.message + (d.check ? ` [${d.check}]` : '')),
    );
    if (d.help) li.append(el('span', 'extra', `help: ${d.help}`));
    if (d.call_chain && d.call_chain.length) li.append(el('span', 'extra', `in ${d.call_chain.join(' ← ')}`));
    li.addEventListener('click', () => {
      if (!d.line) return;
      select({ src: d.line }, { revealOutput: true, revealSource: true });
      if (!app.snapshot.read_only) editor.focusLine(d.line);
    });
    return li;
  });
  if (diagnostics.length > 1000) items.push(el('li', 'none', `and ${diagnostics.length - 1000} more`));
  list.replaceChildren(...items);
}

function showSaved() {
  const state = app.snapshot;
  const saved = state && state.saved && !app.dirty;
  const badge = $('saved');
  badge.textContent = saved ? 'saved' : 'unsaved';
  badge.classList.toggle('unsaved', !saved);
  $('save').disabled = !state || state.read_only;
  if (state && !state.conflict) app.conflictKept = false;
  $('conflict').hidden = !(state && state.conflict) || app.conflictKept;
}

function showBusy(busy) {
  $('busy').hidden = !busy;
}

// ── editing ──

function edited() {
  app.dirty = true;
  showSaved();
  clearTimeout(app.editTimer);
  app.editTimer = setTimeout(() => {
    app.editTimer = 0;
    send('/api/source');
  }, DEBOUNCE_MS);
}

/** Sends the editor's text to `url` (/api/source or /api/save). */
async function send(url) {
  app.sending++;
  try {
    const { version } = await post(url, editor.text);
    app.awaited = Math.max(app.awaited, version);
    if (url === '/api/save') message('saved');
  } catch (error) {
    message(`${url === '/api/save' ? 'save' : 'send'} failed: ${error.message}`, true);
  } finally {
    app.sending--;
  }
  refresh();
}

function save() {
  if (!app.snapshot || app.snapshot.read_only) return;
  clearTimeout(app.editTimer);
  app.editTimer = 0;
  send('/api/save');
}

async function command(url, body) {
  try {
    const { version } = await post(url, body);
    app.awaited = Math.max(app.awaited, version);
    refresh();
  } catch (error) {
    message(`${url}: ${error.message}`, true);
  }
}

async function loadFiles() {
  try {
    const { files } = await getJSON('/api/files');
    const select = $('file');
    const current = app.file || '';
    const options = files.map((f) => {
      const o = el('option', '', f);
      o.value = f;
      o.selected = f === current;
      return o;
    });
    if (!files.includes(current)) {
      // The server may name the file by its base name only.
      const match = options.find((o) => o.value.split('/').pop() === current);
      if (match) match.selected = true;
    }
    select.replaceChildren(...options);
  } catch (error) {
    message(`files: ${error.message}`, true);
  }
}

$('file').addEventListener('change', (event) => {
  const path = event.target.value;
  if (app.dirty || (app.snapshot && !app.snapshot.saved)) {
    if (!confirm('The program has unsaved edits. Open another file and lose them?')) {
      loadFiles();
      return;
    }
  }
  clearTimeout(app.editTimer);
  app.editTimer = 0;
  app.dirty = false;
  command('/api/open', JSON.stringify({ path }));
});
$('save').addEventListener('click', save);
$('reload').addEventListener('click', () => {
  clearTimeout(app.editTimer);
  app.editTimer = 0;
  app.dirty = false;
  command('/api/reload', '');
});
$('keep').addEventListener('click', () => {
  // Saving overwrites the file; until then keep the edits and stop asking.
  app.conflictKept = true;
  showSaved();
});

// ── view controls ──

function setTop2d(on) {
  if (!viewer) return;
  viewer.setTop2d(on);
  $('top2d').setAttribute('aria-pressed', String(on));
}

$('top2d').addEventListener('click', () => setTop2d(!viewer?.top2d));

/** The design layer (`ger view --design`): the part coloured as ger compare's heat map. */
function setHeat(on) {
  if (!viewer || (on && !app.snapshot?.design)) return;
  viewer.setHeat(on);
  $('heat').setAttribute('aria-pressed', String(on));
}
$('heat').addEventListener('click', () => setHeat(!viewer?.heat));
$('fit').addEventListener('click', () => viewer?.fit());
const toggleHelp = (show = $('help').hidden) => {
  $('help').hidden = !show;
};
$('helpButton').addEventListener('click', () => toggleHelp());
$('helpClose').addEventListener('click', () => toggleHelp(false));

const STEP = Math.PI / 36; // 5° a key press
const KEYS = {
  j: () => viewer?.rotate(STEP, 0, 0),
  l: () => viewer?.rotate(-STEP, 0, 0),
  i: () => viewer?.rotate(0, STEP, 0),
  m: () => viewer?.rotate(0, -STEP, 0),
  u: () => viewer?.rotate(0, 0, STEP),
  o: () => viewer?.rotate(0, 0, -STEP),
  a: () => viewer?.zoom(1 / 1.15),
  z: () => viewer?.zoom(1.15),
  t: () => setTop2d(!viewer?.top2d),
  d: () => setHeat(!viewer?.heat),
  f: () => viewer?.fit(),
  '?': () => toggleHelp(),
  arrowup: () => stepOutput(-1),
  arrowdown: () => stepOutput(1),
};

function stepOutput(delta) {
  const sel = app.selection;
  const from = sel && 'out' in sel ? sel.out : -1;
  const to = Math.max(0, Math.min(app.output.length - 1, from + delta));
  if (app.output.length) select({ out: to }, { revealOutput: true, revealSource: true });
}

document.addEventListener('keydown', (event) => {
  if ((event.ctrlKey || event.metaKey) && event.key.toLowerCase() === 's') {
    event.preventDefault();
    save();
    return;
  }
  const typing = event.target.closest && event.target.closest('textarea, input, select');
  if (typing) {
    if (event.key === 'Escape') event.target.blur();
    return;
  }
  if (event.ctrlKey || event.metaKey || event.altKey) return;
  if (event.key === 'Escape') {
    toggleHelp(false);
    return;
  }
  const action = KEYS[event.key.toLowerCase()];
  if (action) {
    event.preventDefault();
    action();
  }
});

// ── live updates ──

function connect() {
  const events = new EventSource('/api/events');
  events.addEventListener('open', () => {
    $('conn').textContent = 'live';
    refresh(); // anything missed while disconnected
  });
  events.addEventListener('error', () => {
    $('conn').textContent = 'reconnecting…';
  });
  events.addEventListener('busy', () => showBusy(true));
  events.addEventListener('snapshot', (event) => {
    let version = Infinity;
    try {
      version = JSON.parse(event.data).version;
    } catch {
      // Not the contract's shape: load anyway.
    }
    if (version > app.shown) refresh();
  });
}

window.addEventListener('beforeunload', (event) => {
  if (app.dirty || app.editTimer) event.preventDefault();
});

// For the browser test and the bench: where a world point is on the canvas.
window.gerView = { project: (p) => viewer && viewer.project(p) };

connect();
refresh();
