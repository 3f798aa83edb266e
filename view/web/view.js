// SPDX-License-Identifier: MIT
// cifs view: the page. The server (or, exported, geometry.js) gives the document and its geometry as
// binary buffers; the page draws them with three.js (Debian's libjs-three), sends edits back and
// draws the library's answer. Nothing is evaluated here.
'use strict';
(function () {
  // timing: the last edit's phases, ms from the edit to the end of each (docs/view.md); syncDraw (tests): wait
  // for the GPU to draw (a pixel read back), so that the last phase ends with the picture, not the commands.
  const view = (window.cifsView = { ready: false, checksum: null, pointCount: 0, lastMs: 0, net: [], error: null,
    timing: null, syncDraw: false });
  let marks = {}; // the current edit's performance.now() at the end of each phase
  const mark = (phase) => { marks[phase] = performance.now(); };
  const token = new URLSearchParams(location.search).get('token') || '';
  const api = (name) => 'api/' + name + '?token=' + encodeURIComponent(token);
  const $ = (id) => document.getElementById(id);
  let doc = null; // the document's description
  let params = null; // depth, scheme, levels
  const edits = new Map(); // point index (a BC-IFS: into its nets one after another) -> coordinates
  const weights = new Map(); // point index -> weight (accepted by the server)
  let knots = null; // the knot lists accepted by the server (null: the file's)
  let controller = null; // the geometry request in flight
  let selected = -1; // the highlighted state
  let stateColors = []; // a junction's colour per state (the runner's: each side its own), else empty

  // --- three.js scene ---
  const canvas = $('canvas');
  /// Whether WebGL draws in software (SwiftShader, llvmpipe: no GPU), where 4× multisampling makes a draw
  /// about three times as long (docs/view.md): antialiasing is for a GPU.
  function softwareWebGL() {
    const gl = document.createElement('canvas').getContext('webgl');
    if (!gl) return false;
    let name = gl.getParameter(gl.RENDERER); // Firefox: the driver's; Chromium: "WebKit WebGL"
    const info = /^WebKit/.test(name) && gl.getExtension('WEBGL_debug_renderer_info');
    if (info) name = gl.getParameter(info.UNMASKED_RENDERER_WEBGL);
    const lose = gl.getExtension('WEBGL_lose_context');
    if (lose) lose.loseContext();
    return /SwiftShader|llvmpipe|softpipe|software/i.test(name);
  }
  view.software = softwareWebGL();
  const renderer = new THREE.WebGLRenderer({ canvas, antialias: !view.software, preserveDrawingBuffer: true });
  renderer.setPixelRatio(window.devicePixelRatio || 1);
  const scene = new THREE.Scene();
  scene.background = new THREE.Color(0xf7f7f5);
  const camera = new THREE.PerspectiveCamera(40, 1, 0.001, 1000);
  const controls = new THREE.OrbitControls(camera, canvas);
  scene.add(new THREE.HemisphereLight(0xffffff, 0x667788, 0.7));
  const sun = new THREE.DirectionalLight(0xffffff, 0.6);
  sun.position.set(1, 2, 3);
  scene.add(sun);
  let shapeObject = null, netPoints = null, netLines = null, states = null, colors = null;

  function resize() {
    const r = canvas.parentElement.getBoundingClientRect();
    renderer.setSize(r.width, r.height, false);
    camera.aspect = r.width / Math.max(1, r.height);
    camera.updateProjectionMatrix();
    draw();
  }
  function draw() { renderer.render(scene, camera); }
  controls.addEventListener('change', draw);
  window.addEventListener('resize', resize);

  function status(text, error) {
    $('status').textContent = text;
    $('status').className = error ? 'error' : '';
  }

  // --- the wire format (view::encode_geometry) ---
  function fnv1a(words) { // view::geometry_checksum: FNV-1a a 32-bit word at a time
    let h = 0x811c9dc5;
    for (let i = 0; i < words.length; ++i) h = Math.imul(h ^ words[i], 0x01000193);
    return h >>> 0;
  }
  function parse(buffer) {
    const magic = new TextDecoder().decode(new Uint8Array(buffer, 0, 8));
    if (magic !== 'CIFSVIEW') throw new Error('not a cifs view geometry');
    const length = new DataView(buffer).getUint32(8, true);
    const header = JSON.parse(new TextDecoder().decode(new Uint8Array(buffer, 12, length)));
    let at = 12 + length;
    const take = (Type, n) => { const a = new Type(buffer, at, n); at += 4 * n; return a; };
    const g = { header };
    g.positions = take(Float32Array, header.positions);
    g.triangles = take(Uint32Array, header.triangles);
    g.states = take(Uint32Array, header.states);
    g.net = take(Float32Array, header.net);
    g.netLines = take(Uint32Array, header.net_lines);
    mark('parse');
    g.checksum = fnv1a(new Uint32Array(g.positions.buffer, g.positions.byteOffset, g.positions.length));
    mark('checksum');
    if (g.checksum !== header.checksum) throw new Error('the geometry arrived damaged (checksum)');
    return g;
  }

  // --- drawing ---
  /// The colour of state s (the runner's when the geometry gives them: a junction's sides; else golden-ratio
  /// hues), the selected state's orange and the others faded.
  function stateColor(s) {
    const c = s < stateColors.length ? new THREE.Color().fromArray(stateColors[s]).convertLinearToSRGB()
      : new THREE.Color().setHSL(((s * 0.618034) % 1 + 1) % 1, 0.55, 0.55);
    if (selected >= 0) { if (s === selected) c.setRGB(1, 0.55, 0); else c.lerp(new THREE.Color(0xdddddd), 0.75); }
    return c;
  }
  let colouredFor = -1; // the selected state of the colours
  /// The vertex colours of the states, each state's colour made once (a few states, many vertices).
  function recolor(redraw = true) {
    if (!colors || !states || states.length === 0) return;
    colouredFor = selected;
    const a = colors.array, palette = [];
    for (let i = 0, k = 0; i < states.length; ++i, k += 3) {
      const s = states[i];
      const c = palette[s] || (palette[s] = stateColor(s));
      a[k] = c.r; a[k + 1] = c.g; a[k + 2] = c.b;
    }
    colors.needsUpdate = true;
    if (redraw) draw();
  }
  function equal(a, b) {
    if (a.length !== b.length) return false;
    for (let i = 0; i < a.length; ++i) if (a[i] !== b[i]) return false;
    return true;
  }
  let gridCache = { key: '', index: null };
  /// The two triangles of each cell of a rows × cols grid (view::Geometry::grid), made once per size.
  function gridTriangles([rows, cols]) {
    const key = rows + 'x' + cols;
    if (gridCache.key === key) return gridCache.index;
    const index = new Uint32Array(6 * (rows - 1) * (cols - 1));
    let at = 0;
    for (let i = 0; i + 1 < rows; ++i)
      for (let j = 0; j + 1 < cols; ++j) {
        const v = i * cols + j;
        index.set([v, v + cols, v + cols + 1, v, v + cols + 1, v + 1], at);
        at += 6;
      }
    gridCache = { key, index };
    return index;
  }
  /// The vertex normals of a grid triangulated as gridTriangles does, in one pass over its cells: three.js's
  /// computeVertexNormals (each triangle's cross product added to its corners in index order, the sums
  /// normalised) with the same operations in the same order, so the same floats, without its per-triangle
  /// index reads and Vector3 copies; a cell's left corners are the last cell's right ones.
  function gridNormals(p, [rows, cols], n) {
    n.fill(0);
    for (let i = 0; i + 1 < rows; ++i) {
      // the cell's corners a (i, j), b (i + 1, j), c (i + 1, j + 1), d (i, j + 1)
      let a = 3 * i * cols, b = a + 3 * cols;
      let ax = p[a], ay = p[a + 1], az = p[a + 2], bx = p[b], by = p[b + 1], bz = p[b + 2];
      for (let j = 0; j + 1 < cols; ++j, a += 3, b += 3) {
        const c = b + 3, d = a + 3;
        const cx = p[c], cy = p[c + 1], cz = p[c + 2], dx = p[d], dy = p[d + 1], dz = p[d + 2];
        // (a, b, c): (c - b) × (a - b)
        let ux = cx - bx, uy = cy - by, uz = cz - bz, wx = ax - bx, wy = ay - by, wz = az - bz;
        let x = uy * wz - uz * wy, y = uz * wx - ux * wz, z = ux * wy - uy * wx;
        n[a] += x; n[a + 1] += y; n[a + 2] += z;
        n[b] += x; n[b + 1] += y; n[b + 2] += z;
        n[c] += x; n[c + 1] += y; n[c + 2] += z;
        // (a, c, d): (d - c) × (a - c)
        ux = dx - cx; uy = dy - cy; uz = dz - cz; wx = ax - cx; wy = ay - cy; wz = az - cz;
        x = uy * wz - uz * wy; y = uz * wx - ux * wz; z = ux * wy - uy * wx;
        n[a] += x; n[a + 1] += y; n[a + 2] += z;
        n[c] += x; n[c + 1] += y; n[c + 2] += z;
        n[d] += x; n[d + 1] += y; n[d + 2] += z;
        ax = dx; ay = dy; az = dz; bx = cx; by = cy; bz = cz;
      }
    }
    for (let v = 0; v < n.length; v += 3) {
      const x = n[v], y = n[v + 1], z = n[v + 2], s = 1 / (Math.sqrt(x * x + y * y + z * z) || 1);
      n[v] = x * s; n[v + 1] = y * s; n[v + 2] = z * s;
    }
  }
  /// Tests: what the shown object holds — the checksum of its position buffer, and for a surface how many of
  /// its normal coordinates differ from three.js's computeVertexNormals on the same buffers.
  view.inspect = () => {
    const geometry = shapeObject.geometry, positions = geometry.getAttribute('position').array;
    const shown = { checksum: fnv1a(new Uint32Array(positions.buffer, positions.byteOffset, positions.length)) };
    if (shapeObject.isMesh) {
      const copy = new THREE.BufferGeometry();
      copy.setAttribute('position', geometry.getAttribute('position'));
      copy.setIndex(geometry.getIndex());
      copy.computeVertexNormals();
      const ours = geometry.getAttribute('normal').array, theirs = copy.getAttribute('normal').array;
      shown.normalsDiffer = 0;
      for (let i = 0; i < ours.length; ++i) if (!Object.is(ours[i], theirs[i])) ++shown.normalsDiffer;
    }
    return shown;
  };
  /// The shape's normals, into its normal attribute (made at the first call).
  function normals(geometry, header) {
    if (header.grid[0] === 0) { geometry.computeVertexNormals(); return; }
    let normal = geometry.getAttribute('normal');
    if (!normal) {
      normal = new THREE.BufferAttribute(new Float32Array(geometry.getAttribute('position').count * 3), 3);
      geometry.setAttribute('normal', normal);
    }
    gridNormals(geometry.getAttribute('position').array, header.grid, normal.array);
    normal.needsUpdate = true;
  }
  /// A new object for the shape of g (its kind or size changed).
  function build(g) {
    if (shapeObject) { scene.remove(shapeObject); shapeObject.geometry.dispose(); shapeObject.material.dispose(); }
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute('position', new THREE.BufferAttribute(g.positions, 3));
    colors = new THREE.BufferAttribute(new Float32Array(g.positions.length).fill(0.6), 3);
    geometry.setAttribute('color', colors);
    if (g.header.pieces > 0) { // a BC-IFS: piece i is the segment from point i to point pieces + i
      const n = g.header.pieces, index = new Uint32Array(2 * n);
      for (let i = 0; i < n; ++i) { index[2 * i] = i; index[2 * i + 1] = n + i; }
      geometry.setIndex(new THREE.BufferAttribute(index, 1));
      shapeObject = new THREE.LineSegments(geometry, new THREE.LineBasicMaterial({ vertexColors: THREE.VertexColors }));
    } else if (g.header.kind === 'ifs') {
      shapeObject = pointCloud(geometry);
    } else if (g.header.kind === 'curve') {
      shapeObject = new (g.header.closed ? THREE.LineLoop : THREE.Line)(geometry,
        new THREE.LineBasicMaterial({ vertexColors: THREE.VertexColors }));
    } else {
      geometry.setIndex(new THREE.BufferAttribute(g.header.grid[0] > 0 ? gridTriangles(g.header.grid) : g.triangles, 1));
      mark('index');
      normals(geometry, g.header);
      mark('normals');
      shapeObject = new THREE.Mesh(geometry, new THREE.MeshPhongMaterial({
        vertexColors: THREE.VertexColors, side: THREE.DoubleSide, shininess: 20 }));
    }
    shapeObject.frustumCulled = false; // the whole shape is in view (no bounding sphere made per edit)
    states = g.states;
    recolor(false);
    mark('colours');
    scene.add(shapeObject);
  }
  /// The shape of g into the shown object's buffers (the same kind and sizes): the positions are the
  /// response's own array; the index stays (a grid's, a BC-IFS's) or takes a mesh's new triangles; the
  /// colours are made again only when the states or the selected state changed. Only what changed is uploaded.
  function update(g) {
    const geometry = shapeObject.geometry;
    const position = geometry.getAttribute('position');
    position.array = g.positions;
    position.needsUpdate = true;
    const index = geometry.getIndex();
    if (shapeObject.isMesh && g.header.grid[0] === 0 && !equal(index.array, g.triangles)) { // a mesh's, sent
      index.array = g.triangles;
      index.needsUpdate = true;
    }
    mark('index');
    if (shapeObject.isMesh) normals(geometry, g.header);
    mark('normals');
    const changed = !equal(states, g.states) || colouredFor !== selected;
    states = g.states;
    if (changed) recolor(false);
    mark('colours');
  }
  let shapeKey = '';
  function show(g, frame) {
    const h = g.header;
    stateColors = h.state_colors || [];
    const key = [h.kind, h.pieces, h.closed, h.grid, g.positions.length, g.triangles.length, g.states.length].join();
    if (shapeObject && key === shapeKey) update(g); else build(g);
    shapeKey = key;
    for (const o of [netPoints, netLines]) if (o) { scene.remove(o); o.geometry.dispose(); }
    const geometry = shapeObject.geometry;
    const netGeometry = new THREE.BufferGeometry();
    netGeometry.setAttribute('position', new THREE.BufferAttribute(new Float32Array(g.net), 3));
    netPoints = new THREE.Points(netGeometry, new THREE.PointsMaterial({ color: 0xc02020, size: 8, sizeAttenuation: false }));
    const lineGeometry = new THREE.BufferGeometry();
    lineGeometry.setAttribute('position', netGeometry.getAttribute('position'));
    lineGeometry.setIndex(new THREE.BufferAttribute(g.netLines, 1));
    netLines = new THREE.LineSegments(lineGeometry, new THREE.LineBasicMaterial({ color: 0x999999 }));
    scene.add(netLines, netPoints);
    if (frame) {
      geometry.computeBoundingSphere();
      const s = geometry.boundingSphere;
      controls.target.copy(s.center);
      const flat = doc.dimension === 2; // plane shapes seen from above
      const from = flat ? new THREE.Vector3(0, 0, 1) : new THREE.Vector3(0.6, -1.2, 1.4).normalize();
      camera.position.copy(s.center).add(from.multiplyScalar(3 * s.radius + 1e-9));
      camera.up.set(0, flat ? 1 : 0, flat ? 0 : 1);
      camera.near = s.radius * 0.01; camera.far = s.radius * 100;
      camera.updateProjectionMatrix();
      controls.update();
    }
    view.net = Array.from(g.net);
    view.pointCount = g.positions.length / 3;
    view.checksum = g.checksum;
    const c = g.header.contraction;
    contractivity(c && c.m > 0 ? 'contractive: δ = ' + c.delta.toFixed(6) + ' over ' + c.m + '-step paths' : '', false);
    mark('objects');
    draw();
    mark('render');
    if (view.syncDraw) {
      const gl = renderer.getContext();
      gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, new Uint8Array(4));
      mark('drawn');
    }
  }
  /// A classic IFS: the points of its Hutchinson measure, each coloured by the map applied last.
  function pointCloud(geometry) {
    return new THREE.Points(geometry, new THREE.PointsMaterial({ vertexColors: THREE.VertexColors, size: 2, sizeAttenuation: false }));
  }
  /// The contractivity of the last edit: the runner's figure, or the library's refusal (status 422).
  function contractivity(text, refused) {
    $('contraction').textContent = text;
    $('contraction').className = refused ? 'error' : '';
    view.contractive = !refused;
    view.contraction = text;
  }

  // --- requests ---
  /// The request's params: the page's, with a candidate's knots or weights (not yet accepted) over them.
  function requestParams(candidate) {
    const points = [], nets = [], w = new Map(weights);
    for (const [i, p] of edits) if (doc.nets) nets.push([...netOf(i), ...p]); else points.push([i, ...p]);
    if (candidate && candidate.weight) w.set(candidate.weight[0], candidate.weight[1]);
    const extra = { points };
    if (nets.length) extra.nets = nets;
    if (w.size) extra.weights = Array.from(w, ([i, x]) => [i, x]);
    const k = candidate && candidate.knots ? candidate.knots : knots;
    if (k) extra.knots = k;
    return Object.assign({}, params, extra);
  }
  /// Point i of a BC-IFS's drawn nets (view::Geometry::net: the nets one after another) as [net, index].
  function netOf(i) {
    let n = 0;
    while (i >= doc.nets[n]) i -= doc.nets[n++];
    return [n, i];
  }
  function body(extra) {
    return JSON.stringify(Object.assign({ params: requestParams() }, extra || {}));
  }
  /// Asks for the geometry of the page's params; with a candidate (knots or a weight), the candidate is
  /// kept only when the server accepts it (a refused one is shown, the last good geometry stays).
  async function refresh(frame, candidate) {
    if (window.cifsBaked) return;
    if (controller) controller.abort();
    controller = new AbortController();
    const mine = controller;
    const begun = performance.now(), phases = (marks = {});
    view.ready = false;
    try {
      const sent = requestParams(candidate);
      view.sent = sent; // what the page asked for (tests rebuild it through the library)
      const r = await fetch(api('geometry'), { method: 'POST', body: JSON.stringify({ params: sent }), signal: mine.signal });
      mark('answer');
      if (r.status === 204) return; // superseded by a newer edit
      if (r.status === 422) { // not contractive: the geometry stays, the edit is shown as refused
        const message = (await r.text()).trim();
        contractivity(message.replace(/^cifs view: /, ''), true);
        status('not contractive: the last contractive geometry is shown', true);
        view.ready = true;
        return;
      }
      if (!r.ok) {
        const message = (await r.text()).trim();
        status(message, true);
        if (candidate) { view.refused = message; candidate.refused(message); }
        view.ready = true;
        return;
      }
      const cifs = /dur=([\d.]+)/.exec(r.headers.get('Server-Timing') || ''); // the server's time (server.cpp)
      const buffer = await r.arrayBuffer();
      mark('body');
      const g = parse(buffer);
      if (mine !== controller) return;
      if (candidate) {
        if (candidate.weight) weights.set(candidate.weight[0], candidate.weight[1]);
        if (candidate.knots) { knots = candidate.knots; loadAutomaton(); }
        candidate.accepted();
        view.refused = null;
      }
      show(g, frame);
      view.lastMs = performance.now() - begun;
      view.timing = Object.fromEntries(Object.entries(phases).map(([phase, t]) => [phase, t - begun]));
      view.timing.bytes = buffer.byteLength;
      if (cifs) view.timing.cifs = Number(cifs[1]);
      status(view.pointCount + ' points, ' + view.lastMs.toFixed(0) + ' ms');
      readout();
      view.ready = true;
    } catch (e) {
      if (e.name !== 'AbortError') { status(String(e.message || e), true); view.error = String(e); view.ready = true; }
    }
  }
  const plural = (n, word) => n + ' ' + word + (n === 1 ? '' : 's');
  function readout() {
    $('readout').textContent = doc.kind + ', ' + doc.dimension + '-D\npoints   ' + view.pointCount +
      '\nchecksum ' + (view.checksum >>> 0).toString(16).padStart(8, '0') + '\nedited   ' + plural(edits.size, 'point') +
      (weights.size ? ', ' + plural(weights.size, 'weight') : '') + (knots ? ', knots' : '');
  }

  // --- the panel ---
  function slider(name, range, value, step) {
    const label = document.createElement('label');
    label.textContent = name + ' ' + value;
    const input = document.createElement('input');
    Object.assign(input, { type: 'range', min: range[0], max: range[1], step: step || 1, value, id: name });
    input.addEventListener('input', () => {
      label.textContent = name + ' ' + input.value;
      params[name] = Number(input.value);
      refresh(false);
    });
    $('panel').append(label, input);
  }
  function panel() {
    $('panel').textContent = '';
    if (doc.ranges.depth) slider('depth', doc.ranges.depth, params.depth);
    if (doc.schemes) {
      const label = document.createElement('label');
      label.textContent = 'scheme';
      const select = document.createElement('select');
      select.id = 'scheme';
      for (const s of doc.schemes) select.add(new Option(s, s, false, s === params.scheme));
      select.addEventListener('change', () => { params.scheme = select.value; refresh(false); });
      $('panel').append(label, select);
    }
    if (doc.ranges.levels) slider('levels', doc.ranges.levels, params.levels);
    if (doc.coefficients && doc.coefficients.length) coefficients();
    if (doc.ranges.amplitude) { // the shape's BC-IFS, its free coefficients perturbed (an experiment's "perturbation")
      slider('amplitude', doc.ranges.amplitude, params.amplitude, 0.005);
      const label = document.createElement('label');
      label.textContent = 'seed';
      const seed = document.createElement('input');
      Object.assign(seed, { type: 'number', min: 0, step: 1, value: params.seed, id: 'seed' });
      seed.addEventListener('change', () => { params.seed = Math.max(0, Math.floor(Number(seed.value))); refresh(false); });
      $('panel').append(label, seed);
    }
    knotPanel();
    if (doc.refusal) contractivity(doc.refusal, true);
    const stem = doc.name.replace(/\.[^.]*$/, '');
    $('save-name').value = stem + '-edited.' + (doc.kind === 'mesh' ? 'obj' : 'json');
    view.document = doc;
    view.params = params;
    $('render-name').value = stem + '-edited.png';
  }
  /// The knots (a text field per direction: numbers separated by spaces or commas) and the weight of one
  /// control point (click a point of the net, or type its index). Each edit is a candidate, kept when the
  /// library accepts it (nurbs::validate: non-decreasing, multiplicities at most degree + 1, …) and
  /// shown in red with the server's message when not: the last good geometry stays.
  function knotPanel() {
    if (!doc.knots || doc.points_editable === false) return;
    const box = document.createElement('details');
    box.open = true;
    const summary = document.createElement('summary');
    summary.textContent = 'knots and weights (degree ' + doc.degree.join(', ') + ')';
    box.append(summary);
    const candidate = (input, edit) => Object.assign(edit, {
      accepted: () => input.classList.remove('error'),
      refused: () => input.classList.add('error'),
    });
    doc.knots.forEach((list, k) => {
      const label = document.createElement('label');
      label.textContent = doc.knots.length === 1 ? (doc.closed ? 'breakpoints (one period)' : 'knots') : 'knots in ' + 'uv'[k];
      const input = document.createElement('input');
      Object.assign(input, { type: 'text', id: 'knots-' + k, value: (knots || doc.knots)[k].join(' ') });
      input.addEventListener('change', () => {
        const values = input.value.trim().split(/[\s,]+/).map(Number);
        const next = (knots || doc.knots).map((l, i) => (i === k ? values : l));
        refresh(false, candidate(input, { knots: next }));
      });
      box.append(label, input);
    });
    const label = document.createElement('label');
    label.textContent = 'weight of control point';
    const row = document.createElement('div');
    row.className = 'row';
    const index = document.createElement('input');
    Object.assign(index, { type: 'number', id: 'weight-index', min: 0, max: doc.weights.length - 1, step: 1, value: 0 });
    const weight = document.createElement('input');
    Object.assign(weight, { type: 'number', id: 'weight', min: 0, step: 0.1 });
    const current = () => {
      const i = Math.min(doc.weights.length - 1, Math.max(0, Math.floor(Number(index.value)) || 0));
      return [i, weights.has(i) ? weights.get(i) : doc.weights[i]];
    };
    index.addEventListener('change', () => { weight.value = current()[1]; weight.classList.remove('error'); });
    weight.addEventListener('change', () => refresh(false, candidate(weight, { weight: [current()[0], Number(weight.value)] })));
    weight.value = current()[1];
    view.selectPoint = (i) => { index.value = i; index.dispatchEvent(new Event('change')); };
    row.append(index, weight);
    box.append(label, row);
    $('panel').append(box);
  }
  /// The free coefficients by name, each a slider over its admissible range (docs/view.md).
  function coefficients() {
    const box = document.createElement('details');
    box.open = true;
    const summary = document.createElement('summary');
    summary.textContent = doc.coefficients.length + ' free coefficients' +
      (doc.free_coefficients > doc.coefficients.length ? ' (of ' + doc.free_coefficients + ')' : '');
    box.append(summary);
    for (const c of doc.coefficients) {
      const value = c.name in params.values ? params.values[c.name] : c.value;
      const label = document.createElement('label');
      const show = (v) => { label.textContent = c.name + ' ' + Number(v).toPrecision(6) + '  [' + c.low.toPrecision(4) + ', ' + c.high.toPrecision(4) + ']'; };
      show(value);
      const input = document.createElement('input');
      const step = (c.high - c.low) / 1000 || 1e-6;
      Object.assign(input, { type: 'range', min: c.low, max: c.high, step, value, id: 'coef:' + c.name });
      input.title = c.capped ? 'admissible range (an end is the search cap)' : 'admissible range: contractive at both ends';
      input.addEventListener('input', () => {
        // A range input rounds to its steps from min: the ends are sent as they are.
        const v = Number(input.value);
        params.values = Object.assign({}, params.values, { [c.name]: Math.min(c.high, Math.max(c.low, v)) });
        show(v);
        refresh(false);
      });
      box.append(label, input);
    }
    $('panel').append(box);
  }
  async function save() {
    const r = await fetch(api('save'), { method: 'POST', body: body({ name: $('save-name').value }) });
    const text = await r.text();
    status(r.ok ? 'wrote ' + JSON.parse(text).written : text.trim(), !r.ok);
    view.saved = r.ok ? JSON.parse(text).written : null;
  }
  $('save').addEventListener('click', save);
  async function render() {
    status('rendering…');
    const r = await fetch(api('render'), { method: 'POST', body: body({ name: $('render-name').value }) });
    const text = await r.text();
    status(r.ok ? 'wrote ' + JSON.parse(text).written : text.trim(), !r.ok);
    view.rendered = r.ok ? JSON.parse(text).written : null;
  }
  $('render').addEventListener('click', render);
  async function dimension() {
    $('dimension-readout').textContent = 'measuring…';
    const r = await fetch(api('dimension'), { method: 'POST', body: body() });
    if (!r.ok) { $('dimension-readout').textContent = (await r.text()).trim(); return; }
    const d = await r.json();
    view.dimension = d;
    $('dimension-readout').textContent = 'dimension ' + d.dimension.toFixed(3) + ' ± ' + d.uncertainty.toFixed(3) +
      ' (' + d.route + ')';
  }
  $('dimension').addEventListener('click', dimension);

  // --- the automaton: click a state to light up its pieces ---
  /// The automaton of the shape with the page's knots (a knot edit changes it); none for a mesh.
  function loadAutomaton() {
    selected = -1;
    view.selected = -1;
    if (doc.kind === 'mesh' || doc.automaton === false) { $('automaton').textContent = ''; return; }
    const init = knots ? { method: 'POST', body: body() } : {};
    fetch(api('automaton.svg'), init).then((a) => a.text()).then(automaton);
  }
  function automaton(svg) {
    $('automaton').innerHTML = svg;
    // io::to_svg draws one circle per state, in state order (names "s3", or "(s0,s1)" for a tensor product).
    $('automaton').querySelectorAll('circle').forEach((circle, s) => {
      circle.addEventListener('click', () => {
        selected = selected === s ? -1 : s;
        for (const c of $('automaton').querySelectorAll('circle')) c.classList.remove('selected');
        if (selected >= 0) circle.classList.add('selected');
        view.selected = selected;
        recolor();
      });
    });
  }

  // --- dragging control points ---
  const raycaster = new THREE.Raycaster();
  let dragging = -1;
  const plane = new THREE.Plane();
  function pointer(event) {
    const r = canvas.getBoundingClientRect();
    return new THREE.Vector2(((event.clientX - r.left) / r.width) * 2 - 1, -((event.clientY - r.top) / r.height) * 2 + 1);
  }
  function netPoint(i) {
    const a = netPoints.geometry.getAttribute('position');
    return new THREE.Vector3(a.getX(i), a.getY(i), a.getZ(i));
  }
  /// The client coordinates of control point i (tests drag it from there).
  view.screenOf = (i) => {
    const p = netPoint(i).project(camera);
    const r = canvas.getBoundingClientRect();
    return [r.left + ((p.x + 1) / 2) * r.width, r.top + ((1 - p.y) / 2) * r.height];
  };
  canvas.addEventListener('pointerdown', (event) => {
    if (!netPoints || window.cifsBaked || doc.points_editable === false) return;
    // The nearest control point within 10 pixels.
    let best = -1, bestDistance = 10;
    const n = netPoints.geometry.getAttribute('position').count;
    for (let i = 0; i < n; ++i) {
      const [x, y] = view.screenOf(i);
      const d = Math.hypot(x - event.clientX, y - event.clientY);
      if (d < bestDistance) { best = i; bestDistance = d; }
    }
    if (best < 0) return;
    if (view.selectPoint) view.selectPoint(best);
    dragging = best;
    controls.enabled = false;
    const normal = new THREE.Vector3();
    camera.getWorldDirection(normal);
    if (doc.dimension === 2) normal.set(0, 0, 1); // plane curves stay in their plane
    plane.setFromNormalAndCoplanarPoint(normal, netPoint(best));
    canvas.setPointerCapture(event.pointerId);
    event.preventDefault();
  });
  canvas.addEventListener('pointermove', (event) => {
    if (dragging < 0) return;
    raycaster.setFromCamera(pointer(event), camera);
    const hit = new THREE.Vector3();
    if (!raycaster.ray.intersectPlane(plane, hit)) return;
    const a = netPoints.geometry.getAttribute('position');
    a.setXYZ(dragging, hit.x, hit.y, hit.z);
    a.needsUpdate = true;
    edits.set(dragging, doc.dimension === 2 ? [hit.x, hit.y] : [hit.x, hit.y, hit.z]);
    draw();
    refresh(false);
  });
  const release = () => { if (dragging >= 0) { dragging = -1; controls.enabled = true; } };
  canvas.addEventListener('pointerup', release);
  canvas.addEventListener('pointercancel', release);

  // --- start ---
  function base64(text) {
    const bytes = atob(text);
    const out = new Uint8Array(bytes.length);
    for (let i = 0; i < bytes.length; ++i) out[i] = bytes.charCodeAt(i);
    return out.buffer;
  }
  function start() {
    document.title = 'cifs view: ' + doc.name;
    $('title').textContent = doc.name;
    params = Object.assign({}, doc.params);
    edits.clear();
    weights.clear();
    knots = null;
    $('dimension-readout').textContent = ''; // the last file's
    const select = $('file');
    select.textContent = '';
    for (const name of doc.files || [doc.name]) select.add(new Option(name, name, false, name === doc.name));
    panel();
    resize();
  }
  /// Another file of the folder: the server opens it (its session's kept geometry dropped) and answers its
  /// document; a file it refuses leaves the page on the shape it shows, with the message.
  async function openFile() {
    const name = $('file').value;
    if (controller) controller.abort();
    view.ready = false;
    status('opening ' + name + '…');
    try {
      const r = await fetch(api('open'), { method: 'POST', body: JSON.stringify({ name }) });
      if (!r.ok) {
        const message = (await r.text()).trim();
        status(message, true);
        view.refused = message;
        $('file').value = doc.name;
        view.ready = true;
        return;
      }
      doc = await r.json();
      view.refused = null;
      contractivity('', false);
      start();
      loadAutomaton();
      await refresh(true);
    } catch (e) {
      status(String(e.message || e), true);
      view.ready = true;
    }
  }
  $('file').addEventListener('change', openFile);
  async function load() {
    try {
      if (location.protocol === 'file:' || !token) { // the exported page: geometry.js holds everything
        await new Promise((resolve, reject) => {
          const s = document.createElement('script');
          s.src = 'geometry.js'; s.onload = resolve; s.onerror = () => reject(new Error('geometry.js is missing'));
          document.head.append(s);
        });
        doc = window.cifsBaked.document;
        start();
        $('files').style.display = 'none';
        $('open').style.display = 'none';
        for (const input of $('panel').querySelectorAll('input, select')) input.disabled = true;
        if (window.cifsBaked.automaton) automaton(window.cifsBaked.automaton);
        show(parse(base64(window.cifsBaked.geometry)), true);
        readout();
        status(view.pointCount + ' points (exported page)');
        view.ready = true;
        return;
      }
      const r = await fetch(api('document'));
      if (!r.ok) throw new Error((await r.text()).trim());
      doc = await r.json();
      start();
      loadAutomaton();
      await refresh(true);
    } catch (e) {
      status(String(e.message || e), true);
      view.error = String(e);
      view.ready = true;
    }
  }
  load();
})();
