/* roboscript replay viewer: draws a recorded run (format roboscript-run, version 1).
 *
 * Every element with class "rs-viewer" becomes a viewer. Its data comes from
 *   - a child <script type="application/json" class="rs-data"> holding
 *     {"header": {...}, "frames": [...], "result": {...} | null, "open_at_s": s, "marks": [...]}
 *     with frames as in the file (only what changed since the frame before), or
 *   - a Server-Sent-Events URL in its data-live attribute: events "header" (the header),
 *     "frame" (one frame) and "end" (the result), each carrying JSON.
 * World frame: x mm east, y mm north, headings degrees clockwise from north.
 * The page shows the time, state, action, pose and sensor values as text (data-role=...), so
 * tests and screen readers can read what the picture shows.
 */
(function () {
  "use strict";

  var NESTED = { sensors: true, motors: true, log: true };
  var EVENTS = { tone: true, print: true };
  var SPEEDS = [0.25, 0.5, 1, 2, 4, 8, 16];
  var MAX_PATH_POINTS = 4000;
  var PRINT_MARKS = 200;  /* most marks under the timeline: close prints share one */
  var COLOURS = ["#1565c0", "#ef6c00", "#2e7d32", "#6a1b9a", "#c62828", "#00838f", "#5d4037",
                 "#ad1457"];

  function el(tag, attrs, text) {
    var node = document.createElement(tag);
    if (attrs) {
      for (var key in attrs) {
        if (Object.prototype.hasOwnProperty.call(attrs, key)) node.setAttribute(key, attrs[key]);
      }
    }
    if (text !== undefined) node.textContent = text;
    return node;
  }

  function fmt(value, digits) {
    if (value === null || value === undefined) return "—";
    if (typeof value === "number") return value.toFixed(digits === undefined ? 1 : digits);
    if (Array.isArray(value)) {
      if (value.length === 0) return "none";
      return value.map(function (v) { return fmt(v, 0); }).join(", ");
    }
    return String(value);
  }

  /* Why the mission entered the frame's state, in the student's words (the record's text);
     a graded run's cause is the mission's own account, and says so. */
  function whyText(why) {
    if (!why) return "—";
    var text = typeof why.text === "string" ? why.text : String(why.kind || "—");
    return why.claimed === true ? "the mission says: " + text : text;
  }

  /* The robot and where it ran: a simulated run says so rather than show its sim:// URL; a
     real robot's port as recorded (a browser run's in the page's own words). */
  function robotText(header) {
    var name = String((header.robot || {}).name || "robot");
    var port = typeof header.port === "string" ? header.port : "";
    if (port === "grader") return name + ", simulated by the grader";
    if (port.indexOf("sim://") === 0) return name + ", simulated";
    return port ? name + ", " + port : name;
  }

  /* When a printed line was printed: its time, or before the start (while the mission
     loaded). */
  function printedAt(p) {
    return p[0] === null ? "before the start" : fmt(p[0], 2) + " s";
  }

  /* Full snapshots from frames holding only changes. */
  function Frames() {
    this.list = [];
    this.current = {};
    this.tones = [];   // [t s, frequency Hz, duration s], in time order
    this.prints = [];  // [t s, line], in time order
  }
  Frames.prototype.push = function (delta) {
    var cur = this.current, key, frame = {};
    if (delta.tone) this.tones.push([delta.t, delta.tone[0], delta.tone[1]]);
    if (delta.print) {
      for (var p = 0; p < delta.print.length; p++) this.prints.push([delta.t, delta.print[p]]);
    }
    for (key in delta) {
      if (!Object.prototype.hasOwnProperty.call(delta, key) || EVENTS[key]) continue;
      if (NESTED[key] && delta[key] && typeof delta[key] === "object") {
        var merged = {}, old = cur[key] || {}, k;
        for (k in old) merged[k] = old[k];
        for (k in delta[key]) merged[k] = delta[key][k];
        cur[key] = merged;
      } else {
        cur[key] = delta[key];
      }
    }
    for (key in cur) frame[key] = cur[key];
    for (key in EVENTS) if (delta[key] !== undefined) frame[key] = delta[key];
    this.list.push(frame);
    return frame;
  };

  /* The numeric series to plot from a frame: sensors, then motors. */
  function series(frame, group) {
    var out = [], values = frame[group] || {}, key;
    for (key in values) {
      var v = values[key];
      if (typeof v === "number" || v === null) out.push([key, v]);
      else if (typeof v === "boolean") out.push([key, v ? 1 : 0]);
      else if (Array.isArray(v) && key === "line") {
        for (var i = 0; i < v.length; i++) out.push([key + "[" + i + "]", v[i]]);
      } else if (Array.isArray(v)) out.push([key, v.length]);
    }
    return out;
  }

  function Viewer(root) {
    this.root = root;
    this.frames = new Frames();
    this.header = null;
    this.result = null;
    this.marks = [];
    this.index = 0;
    this.playing = false;
    this.speed = 1;
    this.playTime = 0;
    this.follow = false;
    this.dirty = true;
    this.plotDirty = true;
    this.pauseAt = "";      // "state:NAME" or "true:LOG NAME": where playing stops by itself
    this.breakKeys = "";    // the choices offered so far (rebuilt when a new one appears)
    this.muted = false;
    this.audio = null;
    this.build();
  }

  Viewer.prototype.q = function (role) {
    return this.root.querySelector("[data-role='" + role + "']");
  };

  Viewer.prototype.build = function () {
    var self = this, root = this.root;
    var bar = el("div", { "class": "rs-bar" });
    this.playButton = el("button", { type: "button", "data-action": "play" }, "▶ Play");
    var back = el("button", { type: "button", "data-action": "step-back",
                              title: "one tick back" }, "◀ tick");
    var step = el("button", { type: "button", "data-action": "step", title: "one tick on" },
                  "tick ▶");
    var speed = el("select", { "data-role": "speed", "aria-label": "speed" });
    SPEEDS.forEach(function (s) {
      var o = el("option", { value: String(s) }, (s < 1 ? (s === 0.25 ? "¼" : "½") : s) + "×");
      if (s === 1) o.selected = true;
      speed.appendChild(o);
    });
    var scrub = el("input", { type: "range", min: "0", max: "0", value: "0", step: "1",
                              "data-role": "scrubber", "aria-label": "time" });
    var time = el("span", { "data-role": "time", "class": "rs-time" }, "0.00 s");
    var pauseAt = el("select", { "data-role": "pause-at", "aria-label": "pause when",
                                 title: "pause the replay when this happens" });
    pauseAt.appendChild(el("option", { value: "" }, "pause at: nothing"));
    var mute = el("button", { type: "button", "data-action": "mute", "aria-pressed": "false",
                              title: "tones are played as the replay passes them" }, "sound: on");
    bar.appendChild(this.playButton);
    bar.appendChild(back);
    bar.appendChild(step);
    bar.appendChild(speed);
    bar.appendChild(scrub);
    bar.appendChild(time);
    bar.appendChild(pauseAt);
    bar.appendChild(mute);
    var timeline = el("div", { "data-role": "timeline", "class": "rs-timeline" });
    var printMarks = el("div", { "data-role": "print-marks", "class": "rs-print-marks" });
    var main = el("div", { "class": "rs-main" });
    this.canvas = el("canvas", { width: "560", height: "420", "class": "rs-world",
                                 role: "img", "aria-label": "the robot in its world" });
    var side = el("div", { "class": "rs-side" });
    side.innerHTML =
      "<dl class='rs-facts'>" +
      "<dt>state</dt><dd data-role='state'>—</dd>" +
      "<dt>why</dt><dd data-role='why'>—</dd>" +
      "<dt>action</dt><dd data-role='action'>—</dd>" +
      "<dt>outcome</dt><dd data-role='outcome'>—</dd>" +
      "<dt>pose</dt><dd data-role='pose'>—</dd>" +
      "<dt>motors</dt><dd data-role='motors'>—</dd>" +
      "<dt>display</dt><dd data-role='display'>—</dd>" +
      "<dt>tone</dt><dd data-role='tone'>—</dd>" +
      "<dt>tick</dt><dd data-role='frame'>—</dd>" +
      "<dt>robot</dt><dd data-role='robot'>—</dd>" +
      "</dl><table class='rs-sensors'><caption>sensors</caption>" +
      "<tbody data-role='sensors'></tbody></table>" +
      "<table class='rs-sensors'><caption>your values (log)</caption>" +
      "<tbody data-role='log'></tbody></table>" +
      "<div class='rs-prints'><span data-role='prints-label'>printed</span>" +
      "<ol data-role='prints'></ol></div>" +
      "<p class='rs-result' data-role='result'></p>";
    main.appendChild(this.canvas);
    main.appendChild(side);
    this.plotCanvas = el("canvas", { width: "860", height: "240", "class": "rs-plot",
                                     role: "img", "aria-label": "sensors and motors over time" });
    var legend = el("div", { "class": "rs-legend", "data-role": "legend" });
    root.appendChild(bar);
    root.appendChild(timeline);
    root.appendChild(printMarks);
    root.appendChild(main);
    root.appendChild(this.plotCanvas);
    root.appendChild(legend);

    this.playButton.addEventListener("click", function () { self.toggle(); });
    back.addEventListener("click", function () { self.pause(); self.seek(self.index - 1); });
    step.addEventListener("click", function () { self.pause(); self.seek(self.index + 1); });
    speed.addEventListener("change", function () { self.speed = parseFloat(speed.value) || 1; });
    pauseAt.addEventListener("change", function () { self.pauseAt = pauseAt.value; });
    mute.addEventListener("click", function () {
      self.muted = !self.muted;
      mute.setAttribute("aria-pressed", self.muted ? "true" : "false");
      mute.textContent = self.muted ? "sound: off" : "sound: on";
    });
    this.pauseAtSelect = pauseAt;
    scrub.addEventListener("input", function () { self.seek(parseInt(scrub.value, 10)); });
    function jump(ev) {
      var target = ev.target.closest ? ev.target.closest("[data-t]") : null;
      if (target) { self.pause(); self.seekTime(parseFloat(target.getAttribute("data-t"))); }
    }
    timeline.addEventListener("click", jump);
    printMarks.addEventListener("click", jump);
    this.plotCanvas.addEventListener("click", function (ev) {
      var rect = self.plotCanvas.getBoundingClientRect();
      var x = (ev.clientX - rect.left) * self.plotCanvas.width / rect.width;
      var span = self.plotSpan();
      self.pause();
      self.seekTime(span[0] + (x - 40) / (self.plotCanvas.width - 50) * (span[1] - span[0]));
    });
    root.addEventListener("keydown", function (ev) {
      if (ev.target && ev.target.tagName === "SELECT") return;
      if (ev.key === " ") { ev.preventDefault(); self.toggle(); }
      else if (ev.key === "ArrowRight") { self.pause(); self.seek(self.index + 1); }
      else if (ev.key === "ArrowLeft") { self.pause(); self.seek(self.index - 1); }
    });
    this.scrub = scrub;
    this.timeline = timeline;
    this.printMarks = printMarks;
  };

  /* ---------------------------------------------------------------------------- data */

  Viewer.prototype.setHeader = function (header) {
    this.header = header;
    var robot = header.robot || {};
    this.root.setAttribute("data-mission", (header.mission || {}).name || "");
    this.sensorSpecs = robot.sensors || [];
    // a graded run names what came from the mission's process: its prints are its own words
    var claimed = Array.isArray(header.claimed) && header.claimed.indexOf("print") >= 0;
    this.printedBy = claimed ? "the mission printed (its own words)" : "printed";
    this.q("prints-label").textContent = this.printedBy;
    // what it printed while it loaded, before the start: shown first, at no time of the run
    var before = Array.isArray(header.printed_before_start) ? header.printed_before_start : [];
    this.printedBefore = before.map(function (line) { return [null, String(line)]; });
    this.q("robot").textContent = robotText(header);
    this.timelineDirty = true;
    this.dirty = true;
    this.worldLayer = null;
  };

  Viewer.prototype.addFrame = function (delta) {
    this.frames.push(delta);
    var n = this.frames.list.length;
    this.scrub.max = String(Math.max(0, n - 1));
    this.timelineDirty = true;
    this.plotDirty = true;
    this.boundsDirty = true;
    if (this.follow) {
      // live: stop following where the chosen pause happens; the run goes on behind it
      if (this.breakBetween(n - 1, n - 1) >= 0) { this.follow = false; this.pausedLive = true; }
      this.index = n - 1;
    }
    this.dirty = true;
  };

  Viewer.prototype.setResult = function (result) {
    this.result = result;
    var text = "";
    if (result) {
      text = result.outcome + (result.final_state ? " in '" + result.final_state + "'" : "") +
        " after " + fmt(result.duration_s, 2) + " s" + (result.reason ? ": " + result.reason : "");
    }
    this.q("result").textContent = text;
    this.root.setAttribute("data-ended", result ? "1" : "0");
    this.timelineDirty = true;
    this.dirty = true;
  };

  Viewer.prototype.loadEmbedded = function (data) {
    this.setHeader(data.header);
    var list = data.frames || [];
    for (var i = 0; i < list.length; i++) this.frames.push(list[i]);
    this.scrub.max = String(Math.max(0, list.length - 1));
    this.marks = data.marks || [];
    this.timelineDirty = this.plotDirty = this.boundsDirty = true;
    this.setResult(data.result || null);
    if (typeof data.open_at_s === "number") this.seekTime(data.open_at_s);
    else this.seek(0);
  };

  Viewer.prototype.connect = function (url) {
    var self = this, source = new EventSource(url);
    this.follow = true;
    this.source = source;
    source.addEventListener("header", function (ev) { self.setHeader(JSON.parse(ev.data)); });
    source.addEventListener("frame", function (ev) { self.addFrame(JSON.parse(ev.data)); });
    source.addEventListener("end", function (ev) {
      self.setResult(JSON.parse(ev.data));
      source.close();
    });
  };

  /* ------------------------------------------------------------------------- control */

  Viewer.prototype.toggle = function () { if (this.playing) this.pause(); else this.play(); };

  Viewer.prototype.play = function () {
    var n = this.frames.list.length;
    if (n === 0) return;
    if (this.index >= n - 1) this.index = 0;  // play again from the start
    this.follow = false;
    this.playing = true;
    this.playTime = this.frames.list[this.index].t;
    this.lastWall = null;
    this.playButton.textContent = "❚❚ Pause";
    this.root.setAttribute("data-playing", "1");
  };

  Viewer.prototype.pause = function () {
    this.playing = false;
    this.playButton.textContent = "▶ Play";
    this.root.setAttribute("data-playing", "0");
  };

  Viewer.prototype.seek = function (index) {
    var n = this.frames.list.length;
    if (n === 0) return;
    this.index = Math.max(0, Math.min(n - 1, index));
    this.follow = this.source !== undefined && this.index === n - 1;
    this.playTime = this.frames.list[this.index].t;
    this.dirty = true;
    this.render();
  };

  Viewer.prototype.indexAt = function (t) {
    var list = this.frames.list, lo = 0, hi = list.length - 1;
    if (hi < 0) return 0;
    if (t <= list[0].t) return 0;
    while (lo < hi) {  // the last frame at or before t
      var mid = (lo + hi + 1) >> 1;
      if (list[mid].t <= t + 1e-9) lo = mid; else hi = mid - 1;
    }
    return lo;
  };

  Viewer.prototype.seekTime = function (t) { this.seek(this.indexAt(t)); };

  Viewer.prototype.advance = function (wallMs) {
    if (!this.playing) { this.lastWall = null; return; }
    if (this.lastWall !== null) {
      this.playTime += (wallMs - this.lastWall) / 1000 * this.speed;
      var list = this.frames.list;
      var index = this.indexAt(this.playTime);
      if (index > this.index) {
        var stop = this.breakBetween(this.index + 1, index);
        this.soundTones(list[this.index].t, list[stop < 0 ? index : stop].t);
        if (stop >= 0) {
          this.index = stop;
          this.pause();
          this.dirty = true;
          this.lastWall = wallMs;
          return;
        }
      }
      if (index !== this.index) { this.index = index; this.dirty = true; }
      if (index >= list.length - 1 && this.playTime >= list[list.length - 1].t) this.pause();
    }
    this.lastWall = wallMs;
  };

  /* The first frame from `first` to `last` where the chosen pause happens, or -1. */
  Viewer.prototype.breakBetween = function (first, last) {
    var choice = this.pauseAt, list = this.frames.list;
    if (!choice) return -1;
    var colon = choice.indexOf(":"), kind = choice.slice(0, colon), name = choice.slice(colon + 1);
    for (var i = Math.max(1, first); i <= last && i < list.length; i++) {
      var before = list[i - 1], now = list[i];
      if (kind === "state" && now.state === name && now.why !== before.why) return i;
      if (kind === "true" && (now.log || {})[name] === true && (before.log || {})[name] !== true) {
        return i;
      }
    }
    return -1;
  };

  /* Play the tones that start after t0 and no later than t1 (seconds), unless muted. */
  Viewer.prototype.soundTones = function (t0, t1) {
    var tones = this.frames.tones;
    if (this.muted || !tones.length) return;
    var Context = window.AudioContext || window.webkitAudioContext;
    if (!Context) return;
    for (var i = 0; i < tones.length; i++) {
      if (tones[i][0] <= t0 || tones[i][0] > t1) continue;
      try {
        if (!this.audio) this.audio = new Context();
        var ctx = this.audio, osc = ctx.createOscillator(), gain = ctx.createGain();
        osc.frequency.value = tones[i][1];
        gain.gain.value = 0.08;
        osc.connect(gain);
        gain.connect(ctx.destination);
        osc.start();
        osc.stop(ctx.currentTime + Math.min(tones[i][2] / this.speed, 5));
      } catch (e) { this.muted = true; return; }  // no sound here: the tone row still shows it
    }
  };

  /* The pause choices: entering each state, and each true/false value the mission logs. */
  Viewer.prototype.offerBreaks = function () {
    var names = (((this.header || {}).mission || {}).states || []).map(function (s) {
      return s.name;
    });
    var flags = Object.keys(this.frames.current.log || {}).filter(function (k) {
      return typeof this.frames.current.log[k] === "boolean";
    }, this);
    var keys = names.join("\n") + "\t" + flags.join("\n");
    if (keys === this.breakKeys) return;
    this.breakKeys = keys;
    var select = this.pauseAtSelect, chosen = select.value;
    while (select.options.length > 1) select.remove(1);
    names.forEach(function (n) {
      select.appendChild(el("option", { value: "state:" + n }, "pause at: entering " + n));
    });
    flags.forEach(function (n) {
      select.appendChild(el("option", { value: "true:" + n }, "pause at: " + n + " becomes true"));
    });
    select.value = chosen;
    if (select.value !== chosen) { select.value = ""; this.pauseAt = ""; }
  };

  /* ------------------------------------------------------------------------- drawing */

  Viewer.prototype.computeBounds = function () {
    var h = this.header || {}, world = h.world, robot = h.robot || {};
    var xs = [], ys = [], i;
    function add(x, y) { xs.push(x); ys.push(y); }
    if (world) {
      (world.walls || []).forEach(function (s) { add(s[0], s[1]); add(s[2], s[3]); });
      (world.lines || []).forEach(function (l) {
        l.segments.forEach(function (s) { add(s[0], s[1]); add(s[2], s[3]); });
      });
      (world.regions || []).forEach(function (r) {
        if (r.radius_mm) { add(r.center[0] - r.radius_mm, r.center[1] - r.radius_mm);
                           add(r.center[0] + r.radius_mm, r.center[1] + r.radius_mm); }
        else r.points.forEach(function (p) { add(p[0], p[1]); });
      });
    }
    var list = this.frames.list, stride = Math.max(1, Math.floor(list.length / 2000));
    for (i = 0; i < list.length; i += stride) if (list[i].pose) add(list[i].pose[0], list[i].pose[1]);
    if (list.length && list[list.length - 1].pose) {
      add(list[list.length - 1].pose[0], list[list.length - 1].pose[1]);
    }
    var r = (robot.body_radius_mm || 100) * 1.5;
    if (!xs.length) add(0, 0);
    var minX = Math.min.apply(null, xs) - r, maxX = Math.max.apply(null, xs) + r;
    var minY = Math.min.apply(null, ys) - r, maxY = Math.max.apply(null, ys) + r;
    if (maxX - minX < 600) { var cx = (maxX + minX) / 2; minX = cx - 300; maxX = cx + 300; }
    if (maxY - minY < 600) { var cy = (maxY + minY) / 2; minY = cy - 300; maxY = cy + 300; }
    var c = this.canvas, scale = Math.min(c.width / (maxX - minX), c.height / (maxY - minY));
    this.view = { minX: minX, maxY: maxY, scale: scale,
                  offX: (c.width - (maxX - minX) * scale) / 2,
                  offY: (c.height - (maxY - minY) * scale) / 2 };
    this.worldLayer = null;
    this.pathIndex = null;
    this.boundsDirty = false;
  };

  Viewer.prototype.px = function (x, y) {
    var v = this.view;
    return [v.offX + (x - v.minX) * v.scale, v.offY + (v.maxY - y) * v.scale];
  };

  Viewer.prototype.drawWorld = function () {
    var c = document.createElement("canvas");
    c.width = this.canvas.width;
    c.height = this.canvas.height;
    var g = c.getContext("2d"), self = this, world = (this.header || {}).world;
    g.fillStyle = "#fafafa";
    g.fillRect(0, 0, c.width, c.height);
    if (world) {
      (world.regions || []).forEach(function (r) {
        g.beginPath();
        if (r.radius_mm) {
          var p = self.px(r.center[0], r.center[1]);
          g.arc(p[0], p[1], r.radius_mm * self.view.scale, 0, 2 * Math.PI);
        } else {
          r.points.forEach(function (q, i) {
            var p = self.px(q[0], q[1]);
            if (i) g.lineTo(p[0], p[1]); else g.moveTo(p[0], p[1]);
          });
          g.closePath();
        }
        g.fillStyle = "rgba(46,125,50,0.12)";
        g.fill();
        g.strokeStyle = "#2e7d32";
        g.setLineDash([4, 3]);
        g.stroke();
        g.setLineDash([]);
        var at = self.px(r.center[0], r.center[1]);
        g.fillStyle = "#1b5e20";
        g.font = "12px sans-serif";
        g.fillText(r.name, at[0] + 3, at[1] - 3);
      });
      g.lineCap = "round";
      (world.lines || []).forEach(function (l) {
        g.strokeStyle = "#333";
        g.lineWidth = Math.max(1, l.width_mm * self.view.scale);
        l.segments.forEach(function (s) {
          var a = self.px(s[0], s[1]), b = self.px(s[2], s[3]);
          g.beginPath(); g.moveTo(a[0], a[1]); g.lineTo(b[0], b[1]); g.stroke();
        });
      });
      g.strokeStyle = "#5d4037";
      g.lineWidth = 3;
      (world.walls || []).forEach(function (s) {
        var a = self.px(s[0], s[1]), b = self.px(s[2], s[3]);
        g.beginPath(); g.moveTo(a[0], a[1]); g.lineTo(b[0], b[1]); g.stroke();
      });
    }
    this.worldLayer = c;
  };

  /* Indices of the frames the path is drawn through: at most MAX_PATH_POINTS. */
  Viewer.prototype.pathPoints = function () {
    var list = this.frames.list, stride = Math.max(1, Math.ceil(list.length / MAX_PATH_POINTS));
    var out = [];
    for (var i = 0; i < list.length; i += stride) if (list[i].pose) out.push(i);
    this.pathIndex = out;
    this.pathLength = list.length;
  };

  Viewer.prototype.drawRobot = function (g, frame) {
    var robot = (this.header || {}).robot || {}, pose = frame.pose;
    if (!pose) return;
    var scale = this.view.scale, h = pose[2] * Math.PI / 180;
    var fx = Math.sin(h), fy = Math.cos(h), rx = fy, ry = -fx;  // forward and right, world
    var self = this, sensors = frame.sensors || {};
    function at(forward, right) {
      return self.px(pose[0] + fx * forward + rx * right, pose[1] + fy * forward + ry * right);
    }
    this.sensorSpecs.forEach(function (s) {
      if (s.kind === "range") {
        var o = at(s.forward_mm, s.right_mm), b = h + s.bearing_deg * Math.PI / 180;
        var reading = sensors[s.name], len = reading === null || reading === undefined ?
          s.max_range_mm : reading, half = s.cone_deg / 2 * Math.PI / 180;
        var dx = Math.sin(b), dy = Math.cos(b);
        g.fillStyle = "rgba(21,101,192,0.10)";
        g.beginPath();
        g.moveTo(o[0], o[1]);
        var a1 = b - half, a2 = b + half;
        g.lineTo(o[0] + Math.sin(a1) * len * scale, o[1] - Math.cos(a1) * len * scale);
        g.lineTo(o[0] + Math.sin(a2) * len * scale, o[1] - Math.cos(a2) * len * scale);
        g.closePath();
        g.fill();
        g.strokeStyle = "#1565c0";
        g.lineWidth = 1.5;
        if (reading === null || reading === undefined) g.setLineDash([5, 4]);
        g.beginPath();
        g.moveTo(o[0], o[1]);
        g.lineTo(o[0] + dx * len * scale, o[1] - dy * len * scale);
        g.stroke();
        g.setLineDash([]);
      }
    });
    var c = this.px(pose[0], pose[1]), radius = (robot.body_radius_mm || 100) * scale;
    g.beginPath();
    g.arc(c[0], c[1], radius, 0, 2 * Math.PI);
    g.fillStyle = "rgba(255,193,7,0.55)";
    g.fill();
    g.lineWidth = 2;
    g.strokeStyle = frame.contact ? "#c62828" : "#6d4c00";
    g.stroke();
    var tip = at(robot.body_radius_mm || 100, 0);
    g.beginPath();
    g.moveTo(c[0], c[1]);
    g.lineTo(tip[0], tip[1]);
    g.strokeStyle = "#3e2723";
    g.stroke();
    this.sensorSpecs.forEach(function (s) {
      if (s.kind === "line") {
        var values = sensors[s.name] || [];
        s.spots_mm.forEach(function (spot, i) {
          var p = at(spot[0], spot[1]);
          g.beginPath();
          g.arc(p[0], p[1], Math.max(2.5, s.spot_diameter_mm * scale), 0, 2 * Math.PI);
          g.fillStyle = (values[i] || 0) > 500 ? "#000" : "#fff";
          g.fill();
          g.strokeStyle = "#c62828";
          g.lineWidth = 1;
          g.stroke();
        });
      }
    });
  };

  Viewer.prototype.draw = function () {
    var g = this.canvas.getContext("2d"), list = this.frames.list;
    if (!this.header) return;
    if (this.boundsDirty || !this.view) this.computeBounds();
    if (!this.worldLayer) this.drawWorld();
    g.drawImage(this.worldLayer, 0, 0);
    if (!list.length) return;
    if (!this.pathIndex || this.pathLength !== list.length) this.pathPoints();
    var idx = this.pathIndex, self = this;
    g.strokeStyle = "#1565c0";
    g.lineWidth = 2;
    g.beginPath();
    var started = false;
    for (var i = 0; i < idx.length && idx[i] <= this.index; i++) {
      var p = self.px(list[idx[i]].pose[0], list[idx[i]].pose[1]);
      if (started) g.lineTo(p[0], p[1]); else { g.moveTo(p[0], p[1]); started = true; }
    }
    var frame = list[this.index];
    if (frame.pose && started) {
      var q = self.px(frame.pose[0], frame.pose[1]);
      g.lineTo(q[0], q[1]);
    }
    g.stroke();
    this.drawRobot(g, frame);
    this.drawScaleBar(g);
  };

  /* A bar of a round length (10 cm, 20 cm, 50 cm, 1 m, ...) in the map's bottom-left corner. */
  Viewer.prototype.drawScaleBar = function (g) {
    var scale = this.view.scale, lengths = [50, 100, 200, 500, 1000, 2000, 5000, 10000];
    var mm = lengths[0];
    for (var i = 0; i < lengths.length; i++) if (lengths[i] * scale <= 120) mm = lengths[i];
    var x = 12, y = this.canvas.height - 14, w = mm * scale;
    g.strokeStyle = "#222";
    g.lineWidth = 2;
    g.beginPath(); g.moveTo(x, y - 4); g.lineTo(x, y); g.lineTo(x + w, y); g.lineTo(x + w, y - 4);
    g.stroke();
    g.fillStyle = "#222";
    g.font = "11px sans-serif";
    g.fillText(mm >= 1000 ? mm / 1000 + " m" : mm / 10 + " cm", x + w + 6, y);
    this.root.setAttribute("data-scale-mm", String(mm));
  };

  Viewer.prototype.plotSpan = function () {
    var list = this.frames.list;
    if (!list.length) return [0, 1];
    return [list[0].t, Math.max(list[list.length - 1].t, list[0].t + 0.001)];
  };

  /* The plot image, without the cursor: one min/max column per pixel, so any length draws
   * in the same time. */
  Viewer.prototype.drawPlot = function () {
    var c = document.createElement("canvas");
    c.width = this.plotCanvas.width;
    c.height = this.plotCanvas.height;
    var g = c.getContext("2d"), list = this.frames.list, legend = this.q("legend");
    g.fillStyle = "#fff";
    g.fillRect(0, 0, c.width, c.height);
    legend.textContent = "";
    this.plotLayer = c;
    if (!list.length) return;
    var span = this.plotSpan(), left = 40, width = c.width - 50, axis = 16;
    var h = c.height - axis, logged = Object.keys(this.frames.current.log || {}).length > 0;
    var panels = logged ?
      [["sensors", 0, h * 0.45], ["log", h * 0.45, h * 0.72], ["motors", h * 0.72, h]] :
      [["sensors", 0, h * 0.62], ["motors", h * 0.62, h]];
    var TITLES = { sensors: "sensors (unit in each name)", log: "your values (log)",
                   motors: "motors (wheel speeds, mm/s)" };
    this.drawTimeAxis(g, span, left, width, h);
    var colour = 0;
    panels.forEach(function (panel) {
      var group = panel[0], top = panel[1] + 6, bottom = panel[2] - 6;
      var names = {}, order = [], lo = Infinity, hi = -Infinity, i, j;
      var stride = Math.max(1, Math.floor(list.length / (width * 4)));
      for (i = 0; i < list.length; i += stride) {
        var s = series(list[i], group);
        for (j = 0; j < s.length; j++) {
          if (s[j][1] === null) continue;  // a sensor that never read is not plotted
          if (!(s[j][0] in names)) { names[s[j][0]] = order.length; order.push(s[j][0]); }
          lo = Math.min(lo, s[j][1]);
          hi = Math.max(hi, s[j][1]);
        }
      }
      if (!order.length) return;
      if (lo === hi) { lo -= 1; hi += 1; }
      g.strokeStyle = "#ddd";
      g.strokeRect(left, top, width, bottom - top);
      g.fillStyle = "#555";
      g.font = "10px sans-serif";
      g.fillText(TITLES[group], left + 4, top + 10);
      g.fillText(String(Math.round(hi)), 2, top + 9);
      g.fillText(String(Math.round(lo)), 2, bottom);
      order.forEach(function (name) {
        var col = COLOURS[colour++ % COLOURS.length];
        var item = el("span", { "class": "rs-key" });
        var swatch = el("i", { style: "background:" + col });
        item.appendChild(swatch);
        item.appendChild(document.createTextNode(group + " " + name));
        legend.appendChild(item);
        g.strokeStyle = col;
        g.lineWidth = 1.3;
        g.beginPath();
        var pen = false;
        for (i = 0; i < list.length; i += stride) {
          var pairs = series(list[i], group), v = null;
          for (j = 0; j < pairs.length; j++) if (pairs[j][0] === name) v = pairs[j][1];
          if (v === null) { pen = false; continue; }
          var x = left + (list[i].t - span[0]) / (span[1] - span[0]) * width;
          var y = bottom - (v - lo) / (hi - lo) * (bottom - top);
          if (pen) g.lineTo(x, y); else { g.moveTo(x, y); pen = true; }
        }
        g.stroke();
      });
    });
    this.plotDirty = false;
  };

  /* The time axis under the plots: ticks at a round step, labelled in seconds. */
  Viewer.prototype.drawTimeAxis = function (g, span, left, width, y) {
    var length = span[1] - span[0], steps = [0.1, 0.2, 0.5, 1, 2, 5, 10, 20, 30, 60, 120, 300,
                                               600, 1200, 1800, 3600];
    var step = steps[steps.length - 1];
    for (var k = 0; k < steps.length; k++) if (length / steps[k] <= 10) { step = steps[k]; break; }
    g.strokeStyle = "#999";
    g.fillStyle = "#555";
    g.font = "10px sans-serif";
    g.beginPath(); g.moveTo(left, y + 2); g.lineTo(left + width, y + 2); g.stroke();
    for (var t = Math.ceil(span[0] / step) * step; t <= span[1] + 1e-9; t += step) {
      var x = left + (t - span[0]) / length * width;
      g.beginPath(); g.moveTo(x, y + 2); g.lineTo(x, y + 6); g.stroke();
      g.fillText(String(Math.round(t * 10) / 10), x - 6, y + 15);
    }
    g.fillText("time (s)", left + width - 40, y + 15);
  };

  Viewer.prototype.drawPlotCursor = function () {
    var g = this.plotCanvas.getContext("2d"), list = this.frames.list;
    if (this.plotDirty || !this.plotLayer) this.drawPlot();
    g.drawImage(this.plotLayer, 0, 0);
    if (!list.length) return;
    var span = this.plotSpan(), left = 40, width = this.plotCanvas.width - 50;
    var self = this;
    this.marks.forEach(function (m) {
      var mx = left + (m.t - span[0]) / (span[1] - span[0]) * width;
      g.strokeStyle = "#c62828";
      g.setLineDash([3, 3]);
      g.beginPath(); g.moveTo(mx, 0); g.lineTo(mx, self.plotCanvas.height); g.stroke();
      g.setLineDash([]);
    });
    var x = left + (list[this.index].t - span[0]) / (span[1] - span[0]) * width;
    g.strokeStyle = "#000";
    g.lineWidth = 1;
    g.beginPath(); g.moveTo(x, 0); g.lineTo(x, this.plotCanvas.height); g.stroke();
  };

  Viewer.prototype.drawTimeline = function () {
    var list = this.frames.list, box = this.timeline;
    box.textContent = "";
    this.timelineDirty = false;
    if (!list.length) return;
    var span = this.plotSpan(), start = 0, states = [];
    for (var i = 1; i <= list.length; i++) {
      // a new segment at each transition, even one back into the same state
      if (i === list.length || list[i].state !== list[start].state ||
          list[i].why !== list[start].why) {
        states.push([list[start].t, i < list.length ? list[i].t : span[1], list[start].state,
                     whyText(list[start].why)]);
        start = i;
      }
    }
    var names = (((this.header || {}).mission || {}).states || []).map(function (s) {
      return s.name;
    });
    states.forEach(function (s) {
      var part = el("button", { type: "button", "class": "rs-seg", "data-t": String(s[0]),
                                "data-state": s[2], "data-why": s[3],
                                title: s[2] + " from " + fmt(s[0], 2) + " s: " + s[3] },
                    s[2]);
      var k = names.indexOf(s[2]);
      part.style.background = COLOURS[(k < 0 ? 0 : k) % COLOURS.length];
      part.style.flexGrow = String(Math.max(s[1] - s[0], 0.0001));
      box.appendChild(part);
    });
    this.drawPrintMarks(span);
  };

  /* A mark under the timeline where the mission printed (close prints share one); its title
   * holds the lines, and a click jumps there. */
  Viewer.prototype.drawPrintMarks = function (span) {
    var prints = (this.printedBefore || []).concat(this.frames.prints);
    var box = this.printMarks, groups = [], i;
    var length = Math.max(span[1] - span[0], 1e-9);  // a run of one frame has no length
    box.textContent = "";
    box.setAttribute("data-count", String(prints.length));
    for (i = 0; i < prints.length; i++) {
      // a line printed before the start is marked at the start
      var t = prints[i][0] === null ? span[0] : prints[i][0];
      var at = Math.min(PRINT_MARKS - 1, Math.floor((t - span[0]) / length * PRINT_MARKS));
      var last = groups[groups.length - 1];
      if (last && last.at === at) last.lines.push(prints[i]);
      else groups.push({ at: at, t: t, lines: [prints[i]] });
    }
    var by = this.printedBy || "printed";
    groups.forEach(function (g) {
      var shown = g.lines.slice(0, 3).map(function (p) { return printedAt(p) + "  " + p[1]; });
      if (g.lines.length > 3) shown.push("(and " + (g.lines.length - 3) + " more)");
      var text = by + ":\n" + shown.join("\n");
      var mark = el("button", { type: "button", "class": "rs-print-mark",
                                "data-t": String(g.t), title: text,
                                "aria-label": text });
      mark.style.left = (100 * (g.t - span[0]) / length) + "%";
      box.appendChild(mark);
    });
  };

  Viewer.prototype.showText = function () {
    var list = this.frames.list, frame = list[this.index];
    if (!frame) return;
    this.q("time").textContent = fmt(frame.t, 2) + " s";
    this.q("state").textContent = frame.state || "—";
    this.q("action").textContent = frame.action || "—";
    this.q("why").textContent = whyText(frame.why);
    var last = this.index === list.length - 1 && this.result;
    this.q("outcome").textContent = frame.outcome || (last ? this.result.outcome : "running");
    this.q("pose").textContent = frame.pose ?
      "x " + fmt(frame.pose[0]) + " mm, y " + fmt(frame.pose[1]) + " mm, heading " +
      fmt(frame.pose[2]) + "°" : "—";
    var m = frame.motors;
    this.q("motors").textContent = m ? Object.keys(m).map(function (k) {
      return k + " " + fmt(m[k]);
    }).join(", ") : "—";
    this.q("display").textContent = frame.display === undefined ? "—" : frame.display;
    var tone = this.toneAt(frame.t);
    this.q("tone").textContent = tone ? fmt(tone[1], 0) + " Hz for " + fmt(tone[2], 2) +
      " s (from " + fmt(tone[0], 2) + " s)" : "—";
    this.showLog(frame);
    this.showPrints(frame.t);
    this.offerBreaks();
    this.q("frame").textContent = (this.index + 1) + " / " + list.length;
    var body = this.q("sensors"), values = frame.sensors || {};
    var keys = Object.keys(values), shown = JSON.stringify(keys);
    if (this.sensorKeys !== shown) {
      // rows are found by position, never by a selector built from a name: a sensor may be
      // called anything (a quote, "</script>")
      body.textContent = "";
      this.sensorCells = keys.map(function (k) {
        var row = el("tr", { "data-sensor": k });
        var cell = el("td", { "class": "rs-value" }, "");
        row.appendChild(el("th", { scope: "row" }, k));
        row.appendChild(cell);
        body.appendChild(row);
        return cell;
      });
      this.sensorKeys = shown;
    }
    var cells = this.sensorCells;
    keys.forEach(function (k, i) { cells[i].textContent = fmt(values[k]); });
    this.scrub.value = String(this.index);
    this.root.setAttribute("data-index", String(this.index));
    this.root.setAttribute("data-t", String(frame.t));
    var segs = this.timeline.children;
    for (var i = 0; i < segs.length; i++) {
      var t0 = parseFloat(segs[i].getAttribute("data-t"));
      var t1 = i + 1 < segs.length ? parseFloat(segs[i + 1].getAttribute("data-t")) : Infinity;
      segs[i].setAttribute("aria-current", frame.t >= t0 && frame.t < t1 ? "true" : "false");
    }
  };

  /* The tone sounding at time t: [start s, Hz, duration s], or null. */
  Viewer.prototype.toneAt = function (t) {
    var tones = this.frames.tones;
    for (var i = tones.length - 1; i >= 0; i--) {
      if (tones[i][0] <= t + 1e-9) return t < tones[i][0] + tones[i][2] - 1e-9 ? tones[i] : null;
    }
    return null;
  };

  /* The student's own values at this frame; rows are kept by reference, never looked up by a
   * selector built from a name. */
  Viewer.prototype.showLog = function (frame) {
    var body = this.q("log"), values = frame.log || {}, keys = Object.keys(values);
    if (!this.logCells || this.logKeys !== keys.join("\n")) {
      body.textContent = "";
      this.logCells = {};
      for (var i = 0; i < keys.length; i++) {
        var row = el("tr"), cell = el("td", { "class": "rs-value" }, "");
        row.appendChild(el("th", { scope: "row" }, keys[i]));
        row.appendChild(cell);
        body.appendChild(row);
        this.logCells[keys[i]] = cell;
      }
      this.logKeys = keys.join("\n");
    }
    for (var j = 0; j < keys.length; j++) {
      var v = values[keys[j]];
      this.logCells[keys[j]].textContent = typeof v === "boolean" ? String(v) : fmt(v, 3);
    }
  };

  /* The last few lines the mission printed up to time t, each with its time. */
  Viewer.prototype.showPrints = function (t) {
    var prints = (this.printedBefore || []).concat(this.frames.prints);
    var list = this.q("prints"), shown = [];
    for (var i = prints.length - 1; i >= 0 && shown.length < 6; i--) {
      if (prints[i][0] === null || prints[i][0] <= t + 1e-9) shown.unshift(prints[i]);
    }
    var key = shown.map(function (p) { return p[0] + " " + p[1]; }).join("\n");
    if (list.getAttribute("data-key") === key) return;
    list.setAttribute("data-key", key);
    list.textContent = "";
    shown.forEach(function (p) { list.appendChild(el("li", null, printedAt(p) + "  " + p[1])); });
  };

  Viewer.prototype.render = function () {
    if (!this.dirty) return;
    this.dirty = false;
    if (this.timelineDirty) this.drawTimeline();
    if (this.boundsDirty && this.source !== undefined) {
      // live: refit the world at most twice a second, not on every frame
      var now = Date.now();
      if (!this.lastFit || now - this.lastFit > 500) { this.lastFit = now; this.computeBounds(); }
    }
    this.draw();
    if (this.plotDirty && this.source !== undefined) {
      var wall = Date.now();
      if (this.lastPlot && wall - this.lastPlot < 250) this.plotDirty = false;
      else this.lastPlot = wall;
    }
    this.drawPlotCursor();
    this.showText();
    if (!this.root.hasAttribute("data-ready-ms")) {
      // milliseconds from the page's start to the first picture (tests/bench/bench_replay.py)
      this.root.setAttribute("data-ready-ms", String(Math.round(performance.now())));
    }
    this.root.setAttribute("data-ready", "1");
  };

  var viewers = [];

  function loop(wallMs) {
    for (var i = 0; i < viewers.length; i++) {
      viewers[i].advance(wallMs);
      viewers[i].render();
    }
    window.requestAnimationFrame(loop);
  }

  function mount(root) {
    if (root.rsViewer) return root.rsViewer;
    var viewer = new Viewer(root);
    root.rsViewer = viewer;
    viewers.push(viewer);
    var data = root.querySelector("script.rs-data");
    var live = root.getAttribute("data-live");
    if (data) viewer.loadEmbedded(JSON.parse(data.textContent));
    else if (live) viewer.connect(live);
    viewer.render();
    return viewer;
  }

  function mountAll() {
    var roots = document.querySelectorAll(".rs-viewer");
    for (var i = 0; i < roots.length; i++) mount(roots[i]);
    window.requestAnimationFrame(loop);
  }

  window.roboscriptViewer = { mount: mount, viewers: viewers };
  if (document.readyState === "loading") document.addEventListener("DOMContentLoaded", mountAll);
  else mountAll();
})();
