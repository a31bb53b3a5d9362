// The viewer page of `holoc view` (embedded by src/export/viewer.rs; three.js is the global
// HOLOC3D, bundled by scripts/bundle_viewer.sh). It reads the page's JSON data (the GLB in
// base64, room labels, object facts and relations), shows the house with orbit controls, labels
// the rooms and tells what a clicked object is. `#top` in the address shows a fixed top view
// without labels (what the tests compare); `#look=NAME` looks closely at the object of that
// instance name (`cat_tree-0`) from its front; `#click=NAME` also clicks it (what the tests do).
// Objects are found by their node's `userData` (room and instance name), never by the node's
// name, which three.js rewrites. With `data.compare` (`holoc view BEFORE AFTER`), moved objects
// get an arrow from where they stood, added ones are green and removed ones a red box. When the
// house is loaded, the element #status says `loaded: N objects` and the console logs
// `holoc-view: N objects`.
(function () {
  "use strict";
  const T = HOLOC3D;
  const data = JSON.parse(document.getElementById("holoc-data").textContent);
  const status = document.getElementById("status");
  const panel = document.getElementById("panel");
  const topView = location.hash === "#top";
  const lookAt = location.hash.startsWith("#look=")
    ? decodeURIComponent(location.hash.slice(6))
    : location.hash.startsWith("#click=")
      ? decodeURIComponent(location.hash.slice(7))
      : null;
  const clickIt = location.hash.startsWith("#click=");
  // The facts of each object by its room and instance name (what its node's userData holds).
  const key = (room, name) => String(room) + "\u0000" + String(name);
  const facts = new Map();
  for (const [id, f] of Object.entries(data.objects || {})) {
    facts.set(key(f.roomId, f.objectName), Object.assign({ id: id }, f));
  }
  const factsOf = (node) => facts.get(key(node.userData.roomId, node.userData.objectName)) || null;
  const roomsById = new Map((data.rooms || []).map((r) => [r.id, r]));
  if (topView) document.body.classList.add("top");

  const renderer = new T.WebGLRenderer({ antialias: !topView, preserveDrawingBuffer: true });
  renderer.setPixelRatio(topView ? 1 : window.devicePixelRatio);
  renderer.setSize(window.innerWidth, window.innerHeight);
  renderer.outputColorSpace = T.SRGBColorSpace;
  document.getElementById("app").appendChild(renderer.domElement);
  const labels = new T.CSS2DRenderer();
  labels.setSize(window.innerWidth, window.innerHeight);
  labels.domElement.className = "labels";
  document.getElementById("app").appendChild(labels.domElement);

  const scene = new T.Scene();
  scene.background = new T.Color(0xf2f1ee);
  scene.add(new T.HemisphereLight(0xffffff, 0x8a8577, 2.2));
  const sun = new T.DirectionalLight(0xffffff, 1.4);
  sun.position.set(4, 10, 6);
  scene.add(sun);
  // glTF is right-handed and AI2-THOR (Unity) left-handed: the file holds AI2-THOR's numbers,
  // so z is mirrored here to show the house as AI2-THOR and the SVG plan do (north up).
  const house = new T.Group();
  house.scale.z = -1;
  scene.add(house);

  const aspect = window.innerWidth / Math.max(1, window.innerHeight);
  let camera = new T.PerspectiveCamera(50, aspect, 0.05, 500);
  let controls = null;

  function escapeText(s) {
    return String(s).replace(/[&<>"]/g, (c) => ({ "&": "&amp;", "<": "&lt;", ">": "&gt;", '"': "&quot;" })[c]);
  }

  function frame(box) {
    const size = box.getSize(new T.Vector3());
    const centre = box.getCenter(new T.Vector3());
    const span = Math.max(size.x, size.z, 1);
    if (topView) {
      const pad = 0.3;
      let w = size.x + 2 * pad;
      let h = size.z + 2 * pad;
      if (w / h > aspect) h = w / aspect;
      else w = h * aspect;
      camera = new T.OrthographicCamera(-w / 2, w / 2, h / 2, -h / 2, 0.1, 100);
      camera.up.set(0, 0, -1);
      camera.position.set(centre.x, box.max.y + 10, centre.z);
      camera.lookAt(centre.x, 0, centre.z);
    } else {
      camera.position.set(centre.x - span * 0.35, span * 0.95 + 2, centre.z + span * 0.85);
      controls = new T.OrbitControls(camera, labels.domElement);
      controls.target.set(centre.x, 0.8, centre.z);
      controls.maxPolarAngle = Math.PI * 0.495;
      controls.addEventListener("change", render);
      controls.update();
    }
  }

  // The camera close in front of one object (its front: +z of its own frame, turned and
  // mirrored as the house is), a little from the side and above.
  function look(name) {
    const node = nodeOf(name);
    if (!node) return false;
    const box = new T.Box3().setFromObject(node);
    const centre = box.getCenter(new T.Vector3());
    const size = box.getSize(new T.Vector3());
    const dist = Math.max(size.x, size.y, size.z) * 1.5 + 0.4;
    const front = new T.Vector3(0, 0, 1).transformDirection(node.matrixWorld);
    front.y = 0;
    if (front.lengthSq() < 1e-6) front.set(0, 0, 1);
    front.normalize();
    const side = new T.Vector3().crossVectors(new T.Vector3(0, 1, 0), front);
    camera.position.copy(centre).addScaledVector(front, dist).addScaledVector(side, dist * 0.35);
    camera.position.y = centre.y + dist * 0.4;
    if (controls) {
      controls.target.copy(centre);
      controls.update();
    } else {
      camera.lookAt(centre);
    }
    return true;
  }

  function addLabels() {
    for (const room of data.rooms) {
      const div = document.createElement("div");
      div.className = "room-label";
      div.textContent = roomName(room);
      const label = new T.CSS2DObject(div);
      label.position.set(room.centre[0], 0.05, room.centre[1]);
      house.add(label);
    }
  }

  // A room by its label, with its id in the scene and its type when they differ.
  function roomName(room) {
    const label = room.label || room.id;
    let text = label;
    if (room.sceneId && room.sceneId !== label) text += " · " + room.sceneId;
    if (room.type && room.type !== label && room.type !== room.sceneId) text += " (" + room.type + ")";
    return text;
  }

  function size(node) {
    const s = new T.Box3().setFromObject(node).getSize(new T.Vector3());
    const cm = (v) => Math.round(v * 100);
    return cm(s.x) + " × " + cm(s.z) + " × " + cm(s.y) + " cm (x × z × height, as placed)";
  }

  function describe(node) {
    const x = node.userData;
    const f = x.kind === "object" ? factsOf(node) || {} : {};
    const room = roomsById.get(x.roomId);
    let html = "<h2>" + escapeText(f.id || (room && x.kind === "room" ? roomName(room) : node.name)) + "</h2><dl>";
    const row = (k, v) => {
      if (v !== undefined && v !== null && v !== "") html += "<dt>" + k + "</dt><dd>" + escapeText(v) + "</dd>";
    };
    row("id", f.id);
    row("kind", x.kind);
    row("asset", x.assetId);
    row("type", x.objectType || x.roomType);
    if (x.kind === "object") row("size", size(node));
    row("room", room ? roomName(room) : x.roomId);
    row("on", x.onObject);
    row("material", x.material || x.floorMaterial);
    html += "</dl>";
    const relations = f.relations || [];
    if (relations.length > 0) {
      html += "<h3>relations</h3><ul>";
      for (const r of relations) {
        html += '<li class="' + (r.satisfied ? "kept" : "broken") + '">' + (r.satisfied ? "✓ " : "✗ ") + escapeText(r.constraint) + "</li>";
      }
      html += "</ul>";
    } else if (x.kind === "object" && !data.hasReport) {
      html += '<p class="hint">relations: give the build report with --report</p>';
    }
    panel.innerHTML = html;
    panel.hidden = false;
  }

  const raycaster = new T.Raycaster();
  const pointer = new T.Vector2();
  let down = null;
  labels.domElement.addEventListener("pointerdown", (e) => {
    down = [e.clientX, e.clientY];
  });
  // What is under the pointer (x, y in −1…1): the nearest object, wall, door or window, else
  // the room whose floor it is.
  function pick(x, y) {
    pointer.set(x, y);
    raycaster.setFromCamera(pointer, camera);
    let floor = null;
    for (const hit of raycaster.intersectObject(house, true)) {
      let node = hit.object;
      while (node && !node.userData.kind) node = node.parent;
      if (!node || node.userData.marker) continue;
      if (node.userData.kind !== "room") {
        describe(node);
        return node;
      }
      if (!floor) floor = node;
    }
    if (floor) {
      describe(floor);
      return floor;
    }
    panel.hidden = true;
    return null;
  }
  labels.domElement.addEventListener("pointerup", (e) => {
    if (!down || Math.hypot(e.clientX - down[0], e.clientY - down[1]) > 4) return;
    pick((e.clientX / window.innerWidth) * 2 - 1, -(e.clientY / window.innerHeight) * 2 + 1);
  });

  function nodeOf(name) {
    let node = null;
    house.traverse((o) => {
      if (!node && o.userData.kind === "object" && o.userData.objectName === name) node = o;
    });
    return node;
  }

  // The before/after view: every object node by its id in the house, a unit box to copy for
  // the markers (objects drawn as boxes are unit cubes scaled to their size).
  function showChanges(cmp) {
    const byId = new Map();
    let unit = null;
    house.traverse((o) => {
      if (o.userData.kind !== "object") return;
      const f = factsOf(o);
      if (f) byId.set(f.id, o);
      if (!unit && o.isMesh && o.geometry) {
        const b = o.geometry.boundingBox || (o.geometry.computeBoundingBox(), o.geometry.boundingBox);
        const s = b.getSize(new T.Vector3());
        if (Math.abs(s.x - 1) < 1e-3 && Math.abs(s.y - 1) < 1e-3 && Math.abs(s.z - 1) < 1e-3) unit = o;
      }
    });
    const tint = (node, hex, opacity) => {
      node.traverse((m) => {
        if (!m.isMesh) return;
        m.material = m.material.clone();
        m.material.color = new T.Color(hex);
        if (m.material.emissive) m.material.emissive = new T.Color(hex).multiplyScalar(0.35);
        if (opacity < 1) {
          m.material.transparent = true;
          m.material.opacity = opacity;
        }
      });
    };
    // A copy of the unit box, in AI2-THOR's frame (the house group mirrors z).
    const box = (centre, dims, yawDeg, hex, opacity) => {
      if (!unit) return null;
      const b = unit.clone();
      b.children.length = 0;
      b.userData = { marker: true };
      b.position.set(centre[0], centre[1], centre[2]);
      b.rotation.set(0, (yawDeg * Math.PI) / 180, 0);
      b.scale.set(Math.max(dims[0], 0.01), Math.max(dims[1], 0.01), Math.max(dims[2], 0.01));
      tint(b, hex, opacity);
      house.add(b);
      return b;
    };
    let moved = 0;
    for (const m of cmp.moved || []) {
      const from = m.from;
      const to = m.to;
      const dx = to[0] - from[0];
      const dz = to[2] - from[2];
      const len = Math.hypot(dx, dz);
      const y = Math.max(from[1], to[1]) * 2 + 0.1;
      if (len > 1e-3) {
        // The shaft from where it stood to where it stands, and a head at its end.
        const yaw = (Math.atan2(dx, dz) * 180) / Math.PI;
        box([(from[0] + to[0]) / 2, y, (from[2] + to[2]) / 2], [0.05, 0.05, len], yaw, 0xcc6600, 1);
        box([to[0], y, to[2]], [0.18, 0.18, 0.18], yaw + 45, 0xcc6600, 1);
      }
      box([from[0], from[1], from[2]], [0.12, 0.12, 0.12], 0, 0xcc6600, 0.5);
      moved += 1;
    }
    let added = 0;
    for (const id of cmp.added || []) {
      const node = byId.get(id);
      if (node) {
        tint(node, 0x22aa44, 1);
        added += 1;
      }
    }
    let removed = 0;
    for (const r of cmp.removed || []) {
      if (box(r.at, r.size, r.rotation || 0, 0xdd2222, 0.45)) removed += 1;
    }
    const legend = document.getElementById("compare");
    legend.innerHTML =
      "before: " + escapeText(cmp.before || "") + " · " +
      '<span class="moved">' + moved + " moved (arrows)</span> · " +
      '<span class="added">' + added + " added (green)</span> · " +
      '<span class="removed">' + removed + " removed (red)</span>";
    legend.hidden = false;
    legend.dataset.moved = String(moved);
    legend.dataset.added = String(added);
    legend.dataset.removed = String(removed);
  }

  window.addEventListener("resize", () => {
    const a = window.innerWidth / Math.max(1, window.innerHeight);
    if (camera.isPerspectiveCamera) {
      camera.aspect = a;
      camera.updateProjectionMatrix();
    }
    renderer.setSize(window.innerWidth, window.innerHeight);
    labels.setSize(window.innerWidth, window.innerHeight);
    render();
  });

  // Drawn on demand (after loading, a move of the camera, a resize), not in a loop: a page left
  // open costs nothing, and a software renderer (the headless browser of the tests) keeps up.
  function draw() {
    renderer.render(scene, camera);
    labels.render(scene, camera);
  }
  let pending = false;
  function render() {
    if (pending) return;
    pending = true;
    requestAnimationFrame(() => {
      pending = false;
      draw();
    });
  }

  const bytes = Uint8Array.from(atob(data.glb), (c) => c.charCodeAt(0));
  new T.GLTFLoader().parse(
    bytes.buffer,
    "",
    (gltf) => {
      house.add(gltf.scene);
      let objects = 0;
      gltf.scene.traverse((o) => {
        if (o.userData.kind === "object") objects += 1;
      });
      house.updateMatrixWorld(true);
      frame(new T.Box3().setFromObject(house));
      const looking = !topView && lookAt !== null && look(lookAt);
      if (!topView && !looking) addLabels();
      if (data.compare && !topView) showChanges(data.compare);
      house.updateMatrixWorld(true);
      draw();
      if (looking && clickIt) {
        // A click at the middle of the object as the camera sees it.
        const node = nodeOf(lookAt);
        const centre = new T.Box3().setFromObject(node).getCenter(new T.Vector3()).project(camera);
        const picked = pick(centre.x, centre.y);
        panel.dataset.picked = picked ? picked.userData.objectName || "" : "";
      }
      status.textContent = "loaded: " + objects + " objects";
      status.dataset.objects = String(objects);
      console.log("holoc-view: " + objects + " objects");
    },
    (err) => {
      status.textContent = "error: " + err;
      console.error("holoc-view: " + err);
    }
  );
})();
