// The viewer page of `holoc view` (embedded by src/export/viewer.rs; three.js is the global
// HOLOC3D, bundled by scripts/bundle_viewer.sh). It reads the page's JSON data (the GLB in
// base64, room labels, object facts and relations), shows the house with orbit controls, labels
// the rooms and tells what a clicked object is. `#top` in the address shows a fixed top view
// without labels (what the tests compare); `#look=NAME` looks closely at the object of that
// instance name (`cat_tree-0`) from its front. When the house is loaded, the element #status says
// `loaded: N objects` and the console logs `holoc-view: N objects`.
(function () {
  "use strict";
  const T = HOLOC3D;
  const data = JSON.parse(document.getElementById("holoc-data").textContent);
  const status = document.getElementById("status");
  const panel = document.getElementById("panel");
  const topView = location.hash === "#top";
  const lookAt = location.hash.startsWith("#look=") ? decodeURIComponent(location.hash.slice(6)) : null;
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
    let node = null;
    house.traverse((o) => {
      if (!node && o.userData.kind === "object" && o.userData.objectName === name) node = o;
    });
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
      div.textContent = room.type === room.id ? room.id : room.id + " (" + room.type + ")";
      const label = new T.CSS2DObject(div);
      label.position.set(room.centre[0], 0.05, room.centre[1]);
      house.add(label);
    }
  }

  function describe(node) {
    const x = node.userData;
    const facts = data.objects[node.name] || {};
    let html = "<h2>" + escapeText(node.name) + "</h2><dl>";
    const row = (k, v) => {
      if (v !== undefined && v !== null && v !== "") html += "<dt>" + k + "</dt><dd>" + escapeText(v) + "</dd>";
    };
    row("kind", x.kind);
    row("asset", x.assetId);
    row("type", x.objectType);
    row("room", x.roomId);
    row("on", x.onObject);
    row("material", x.material);
    html += "</dl>";
    const relations = facts.relations || [];
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
  labels.domElement.addEventListener("pointerup", (e) => {
    if (!down || Math.hypot(e.clientX - down[0], e.clientY - down[1]) > 4) return;
    pointer.set((e.clientX / window.innerWidth) * 2 - 1, -(e.clientY / window.innerHeight) * 2 + 1);
    raycaster.setFromCamera(pointer, camera);
    for (const hit of raycaster.intersectObject(house, true)) {
      let node = hit.object;
      while (node && !node.userData.kind) node = node.parent;
      if (node && node.userData.kind !== "room") {
        describe(node);
        return;
      }
    }
    panel.hidden = true;
  });

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
      draw();
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
