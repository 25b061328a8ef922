// scara_opt's part of the page, after meshcat's viewer and the scene: the camera fitted to
// the window, the obstacles' labels, and a control bar (play, time slider, one block per
// move, the instant of least clearance) that needs no menu. SCARA_VIEW is written by
// scara_opt.view (world coordinates: metres, z up).
(function () {
  "use strict";
  var V = SCARA_VIEW, THREE = MeshCat.THREE, an = viewer.animator;
  var el = function (tag, id, text) {
    var e = document.createElement(tag);
    if (id) e.id = id;
    if (text !== undefined) e.textContent = text;
    return e;
  };
  var world = function (p) { return viewer.scene.localToWorld(new THREE.Vector3(p[0], p[1], p[2])); };
  var fmt = function (t) { return t.toFixed(3); };

  // ---- the heading and the control bar
  var title = el("div", "so-title");
  title.appendChild(el("b", null, V.title));
  title.appendChild(el("div", null, V.subtitle));
  document.body.appendChild(title);
  var labels = el("div", "so-labels");
  V.labels.forEach(function (l) {
    var e = el("div", null, l.name);
    e.className = "so-label";
    e.dataset.name = l.name;
    labels.appendChild(e);
  });
  document.body.appendChild(labels);

  var T = V.duration, bar = null, slider = null, play = null, clock = null;
  var playing = false, paused = false;  // paused: by the page, not at the end
  var now = function () {
    return an.actions.reduce(function (acc, a) { return Math.max(acc, a.time); }, 0);
  };
  var show = function (t) {
    slider.value = t;
    clock.textContent = fmt(t) + " / " + fmt(T) + " s";
    an.display_progress(t);  // meshcat's own slider, under "Open Controls"
  };
  var pause = function () { paused = true; an.pause(); };
  var hold = function (on) {  // an action never played is not applied: start it, held still
    an.actions.forEach(function (a) {
      if (!a.isScheduled()) a.play();
      a.paused = on;
    });
  };
  var seek = function (t) {
    if (an.playing) pause();
    hold(true);
    an.seek(t);
    show(t);
  };
  if (T > 0) {
    bar = el("div", "so-bar");
    var row = el("div", "so-row");
    play = el("button", "so-play", "\u25B6 play");
    play.type = "button";
    clock = el("span", "so-clock");
    row.appendChild(play);
    row.appendChild(clock);
    if (V.least) {
      var go = el("button", "so-least-go", "least clearance " + V.least.text);
      go.type = "button";
      go.title = "go to the instant of least clearance";
      go.addEventListener("click", function () { seek(V.least.time); });
      row.appendChild(go);
    } else if (V.least_note) {
      var note = el("span", "so-least-note", V.least_note);
      note.title = V.least_note;
      row.appendChild(note);
    }
    row.appendChild(el("span", "so-note", V.note));
    bar.appendChild(row);
    var track = el("div", "so-track"), blocks = el("div", "so-moves");
    if (!V.moves.length) track.className = "so-bare";
    V.moves.forEach(function (m) {
      var b = el("div"), name = el("span", null, m.label), d = el("span", null);
      b.className = "so-move";
      b.dataset.start = m.start;
      b.dataset.duration = m.duration;
      b.title = "move " + m.label + ": starts at " + fmt(m.start) + " s, lasts " +
        fmt(m.duration) + " s";
      b.style.left = (100 * m.start / T) + "%";
      b.style.width = (100 * m.duration / T) + "%";
      b.appendChild(name);
      b.appendChild(d);
      blocks.appendChild(b);
    });
    track.appendChild(blocks);
    var shorten = function () {  // on each line of a block the longest text that fits
      Array.prototype.forEach.call(blocks.children, function (b, i) {
        var m = V.moves[i], d = m.duration.toFixed(2);
        [[m.label, m.label.split(" ")[0]], [d + " s", d, ""]].forEach(function (texts, j) {
          var line = b.children[j];
          for (var k = 0; k < texts.length; k++) {
            line.textContent = texts[k];
            if (line.scrollWidth <= b.clientWidth) break;
          }
        });
      });
    };
    slider = el("input", "so-time");
    slider.type = "range";
    slider.min = 0;
    slider.max = T;
    slider.step = "any";
    slider.setAttribute("aria-label", "time [s]");
    slider.addEventListener("input", function () { seek(parseFloat(slider.value)); });
    track.appendChild(slider);
    if (V.least) {
      var mark = el("div", "so-least");
      mark.dataset.time = V.least.time;
      mark.style.left = "calc(7px + (100% - 14px) * " + (V.least.time / T) + ")";
      track.appendChild(mark);
    }
    bar.appendChild(track);
    document.body.appendChild(bar);
    shorten();
    window.addEventListener("resize", shorten);
    play.addEventListener("click", function () {
      if (an.playing) { pause(); return; }
      if (now() >= T - 1e-9) an.seek(0);
      paused = false;
      hold(false);
      an.play();
    });
    show(0);
    var tick = function () {
      if (an.playing !== playing) {  // meshcat stops at the end and rewinds: keep the end pose
        playing = an.playing;
        play.textContent = playing ? "\u275A\u275A pause" : "\u25B6 play";
        if (!playing && !paused) seek(T);
      }
      if (playing) show(Math.min(now(), T));
      requestAnimationFrame(tick);
    };
    requestAnimationFrame(tick);
  }

  // ---- the camera: from V.eye, at the distance that fits V.points in the window
  var moved = false;
  viewer.controls.addEventListener("start", function () { moved = true; });
  var fit = function () {
    var cam = viewer.camera, w = window.innerWidth, h = window.innerHeight;
    cam.fov = V.fov;
    cam.aspect = w / h;
    var up = new THREE.Vector3(0, 1, 0);
    var f = world(V.eye).sub(world([0, 0, 0])).normalize().negate();
    var r = new THREE.Vector3().crossVectors(f, up).normalize();
    var u = new THREE.Vector3().crossVectors(r, f);
    var pts = V.points.map(world), target = new THREE.Vector3();
    var box = new THREE.Box3().setFromPoints(pts);
    box.getCenter(target);
    var tv = Math.tan(V.fov * Math.PI / 360), th = tv * cam.aspect, m = 0.03;
    var below = bar ? bar.getBoundingClientRect().height : 0;
    var above = title.getBoundingClientRect().bottom;
    var xl = -1 + m, xr = 1 - m, yb = -1 + 2 * below / h + m, yt = 1 - 2 * above / h - m;
    var D = 1;
    var extent = function (P, D) {
      var e = [Infinity, -Infinity, Infinity, -Infinity];
      P.forEach(function (p) {
        var X = p[0] / ((D + p[2]) * th), Y = p[1] / ((D + p[2]) * tv);
        e[0] = Math.min(e[0], X); e[1] = Math.max(e[1], X);
        e[2] = Math.min(e[2], Y); e[3] = Math.max(e[3], Y);
      });
      return e;
    };
    for (var it = 0; it < 6; it++) {
      var P = pts.map(function (p) {
        var d = p.clone().sub(target);
        return [d.dot(r), d.dot(u), d.dot(f)];
      });
      var lo = 1e-3 - Math.min.apply(null, P.map(function (p) { return p[2]; })), hi = lo + 1e3;
      for (var k = 0; k < 60; k++) {  // the spans shrink as the camera backs off
        var mid = (lo + hi) / 2, e = extent(P, mid);
        if (e[1] - e[0] <= xr - xl && e[3] - e[2] <= yt - yb) hi = mid; else lo = mid;
      }
      D = hi;
      var ex = extent(P, D);
      target.addScaledVector(r, ((ex[0] + ex[1]) / 2 - (xl + xr) / 2) * th * D);
      target.addScaledVector(u, ((ex[2] + ex[3]) / 2 - (yb + yt) / 2) * tv * D);
    }
    cam.near = D / 100;
    cam.far = D * 100;
    cam.position.copy(target).addScaledVector(f, -D);
    cam.updateProjectionMatrix();
    viewer.controls.target.copy(target);
    viewer.controls.update();
    viewer.set_dirty();
  };

  // ---- the labels follow the camera: placed after every render
  var anchors = V.labels.map(function (l) { return world(l.at); });
  var place = function () {
    var w = window.innerWidth, h = window.innerHeight;
    anchors.forEach(function (a, i) {
      var p = a.clone().project(viewer.camera), e = labels.children[i];
      e.style.display = p.z < 1 ? "" : "none";
      e.style.left = ((p.x + 1) / 2 * w) + "px";
      e.style.top = ((1 - p.y) / 2 * h) + "px";
    });
  };
  var render = viewer.render.bind(viewer);
  viewer.render = function () { render(); place(); };
  var refit = function () { if (!moved) fit(); };
  window.addEventListener("resize", refit);
  window.addEventListener("load", refit);
  fit();
})();
