/* roboscript in a browser tab: the editor, check as you type, a run on the simulator, the
 * replay and the state diagram, all from roboscript itself running in Pyodide. Works from
 * file:// with no network: every binary comes from the page's own scripts (window.rsAssets).
 *
 * The student's code runs in a worker of its own (worker.js), never in the page's thread: a
 * loop, a flood of print() or a runaway allocation cannot freeze the page, and Stop ends the
 * worker whole and starts a fresh one. A run on a real robot runs there too; the browser's
 * USB and Bluetooth objects live in the page, which relays the robot's bytes and can stop the
 * robot by itself (robot-port.js).
 */
(function () {
  "use strict";

  function $(role) { return document.querySelector("[data-role='" + role + "']"); }
  function button(action) { return document.querySelector("[data-action='" + action + "']"); }
  function say(text) { $("status").textContent = text; }

  // Pyodide's binaries come from the page's own scripts (answered-fetch.js)
  window.rsAnswerFetch(function () { return window.rsAssets || {}; });

  var editor = null, checkTimer = null, marked = [];
  var written = {};  // every file checked, by name: the page keeps them till it closes
  var worker = null, ready = false, calls = {}, nextCall = 0, busy = 0, checked = 0;
  var runtimeScripts = ["pyodide.asm.wasm", "python_stdlib.zip", "site-packages.zip"];

  /* The worker's Python: started (or started again after Stop), answering calls in order. */
  function startPython() {
    ready = false;
    var started = performance.now();
    var source = new Blob([window.rsWorkerSource], { type: "text/javascript" });
    worker = new Worker(URL.createObjectURL(source));
    var assets = {};
    runtimeScripts.forEach(function (name) { assets[name] = window.rsAssets[name]; });
    return new Promise(function (resolve, reject) {
      worker.onmessage = function (event) {
        var message = event.data;
        if (message.type === "ready") {
          ready = true;
          resolve({ runtimeMs: started + message.runtimeMs });
        } else if (message.type === "failed") {
          reject(new Error(message.error));
        } else if (message.type !== "answer") {
          fromWorker(message);  // a run on a robot: its port, and that it is alive
        } else {
          document.body.setAttribute("data-heap-bytes", String(message.heapBytes));
          var waiting = calls[message.id];
          delete calls[message.id];
          if (message.outOfMemory && message.error === undefined) {
            // once the caller has shown its answer (MemoryError at the student's line)
            window.setTimeout(function () { outOfMemory(); }, 0);
          }
          if (!waiting) return;
          if (message.error === undefined) waiting.resolve(message.value);
          else waiting.reject({ crashed: message.error, fatal: message.fatal,
                                outOfMemory: message.outOfMemory });
        }
      };
      worker.onerror = function (event) {
        event.preventDefault();
        if (!ready) reject(new Error(event.message));
        else endPython({ crashed: event.message, fatal: true });
      };
      worker.postMessage({
        type: "boot", assets: assets, lock: window.rsPyodideLock,
        indexURL: new URL("roboscript-web/", document.baseURI).href
      });
    });
  }

  /* A promise of what Python's ``module.fn(args...)`` answered (JSON text); rejected with
   * {stopped: reason} when the worker was ended first, {crashed: error} when Python failed. */
  function call(module, fn) {
    var args = Array.prototype.slice.call(arguments, 2);
    var id = ++nextCall;
    return new Promise(function (resolve, reject) {
      calls[id] = { resolve: resolve, reject: reject };
      worker.postMessage({ type: "call", id: id, module: module, fn: fn, args: args });
    });
  }

  /* ``call`` of a run on a robot: it waits on the robot, so the worker takes the page's
   * messages meanwhile (webport.py) and holds other calls till it ends. */
  function callWaiting(module, fn) {
    var args = Array.prototype.slice.call(arguments, 2);
    var id = ++nextCall;
    return new Promise(function (resolve, reject) {
      calls[id] = { resolve: resolve, reject: reject };
      worker.postMessage({ type: "call", id: id, module: module, fn: fn, args: args,
                           waits: true });
    });
  }

  /* End the worker at once (a loop in it never returns), and start a fresh one. A robot it
   * was driving is stopped by the page first. */
  function endPython(why) {
    if (robot) haltRobot(robot);
    if (worker) worker.terminate();
    worker = null;
    ready = false;
    var waiting = calls;
    calls = {};
    Object.keys(waiting).forEach(function (id) { waiting[id].reject(why); });
    say("Starting Python again…");
    document.body.setAttribute("data-ready", "restarting");
    showProblems([]);
    startPython().then(function () {
      // the files the student had in the page are written again in the fresh worker
      Object.keys(written).forEach(function (name) {
        if (name !== $("name").value) call("bridge", "check_text", name, written[name], "");
      });
      document.dispatchEvent(new CustomEvent("roboscript-restarted"));
      document.body.setAttribute("data-ready", "1");
      check();
    }).catch(failedToStart);
  }

  function failedToStart(error) {
    say("roboscript could not start in this browser: " + (error && error.message || error));
    document.body.setAttribute("data-ready", "error");
  }

  var OUT_OF_MEMORY = "Python in this page ran out of memory: your code asked for more " +
    "than the 1 GB the page gives it (does it keep making lists or strings that grow " +
    "without end?). The page started Python again: fix the code, then run again.";

  /* A note under the run's result, till the next run or grade: one sentence. */
  function note(text) {
    var shown = $("run-note");
    shown.textContent = text;
    if (text) shown.setAttribute("data-note", text);
    else shown.removeAttribute("data-note");
  }

  /* Python was refused memory and went on (the student's code got MemoryError): the answer
   * is shown, and a fresh Python, with a small heap again, takes the next run. */
  function outOfMemory() {
    note(OUT_OF_MEMORY);
    endPython({ stopped: OUT_OF_MEMORY });
  }

  /* What the page says of a call that did not answer: ended by Stop, or Python itself gave
   * way (out of memory): the worker is started again in both cases. */
  function notAnswered(failure) {
    if (failure && failure.stopped) return failure.stopped;
    var text = String(failure && failure.crashed || failure);
    var memory = failure && failure.outOfMemory || /memory|allocat/i.test(text);
    endPython({ stopped: text });
    if (memory) note(OUT_OF_MEMORY);
    return memory ? OUT_OF_MEMORY :
      "Python in this page stopped unexpectedly (" + text + "); the page started it again.";
  }

  function busyWith(delta) {
    if (delta > 0) note("");
    busy += delta;
    button("stop-run").disabled = busy === 0;
    refreshButtons();
  }

  function mode(name) { return /\.py$/.test(name) ? "python" : "yaml"; }

  function makeEditor() {
    var first = window.rsExamples["hello.yaml"] || "";
    kept = first;
    editor = window.CodeMirror($("editor"), {
      value: first, mode: "yaml", lineNumbers: true, indentUnit: 2, tabSize: 2,
      extraKeys: { Tab: function (cm) { cm.replaceSelection("  "); } },
      viewportMargin: Infinity
    });
    editor.on("change", function () {
      window.clearTimeout(checkTimer);
      checkTimer = window.setTimeout(check, 300);
    });
    var examples = $("example");
    Object.keys(window.rsExamples).forEach(function (name) {
      var option = document.createElement("option");
      option.value = name;
      option.textContent = name;
      examples.appendChild(option);
    });
    examples.addEventListener("change", function () {
      var chosen = examples.value;
      examples.value = "";
      if (!chosen) return;
      unlessUnsaved("picking an example", function () {
        load(chosen, window.rsExamples[chosen]);
      });
    });
    $("name").addEventListener("change", function () {
      editor.setOption("mode", mode($("name").value));
      check();
    });
  }

  function load(name, text) {
    $("name").value = name;
    editor.setOption("mode", mode(name));
    editor.setValue(text);
    kept = text;
  }

  /* The editor's text as last opened, picked or saved: anything else is edits the student
   * would lose if a file replaced them (the page keeps nothing once closed). */
  var kept = null;

  function unsaved() { return kept !== null && editor.getValue() !== kept; }

  /* ``replace`` (Open…, an example) at once, or, when the editor holds edits not saved since
   * the last open or save, once the student said so in the page's dialog; kept otherwise. */
  var replacing = null;  // what the dialog's "Lose them" does

  function unlessUnsaved(doing, replace) {
    if (!unsaved()) { replace(); return; }
    replacing = replace;
    $("unsaved-text").textContent = "Your edits to " + ($("name").value || "this mission") +
      " are not saved, and " + doing + " replaces them. Keep them (then Save, which " +
      "downloads the file), or lose them?";
    if (!$("unsaved").open) $("unsaved").showModal();
  }

  /* The student's answer, acted on within their click (the file chooser opens for a click
   * only); Escape keeps the edits too. */
  function answerUnsaved(lose) {
    var replace = replacing;
    replacing = null;
    if ($("unsaved").open) $("unsaved").close();
    if (lose && replace) replace();
    else editor.focus();
  }

  function showProblems(problems) {
    var list = $("problems");
    list.textContent = "";
    marked.forEach(function (line) { editor.removeLineClass(line, "background", "rs-bad-line"); });
    marked = [];
    problems.forEach(function (p) {
      var item = document.createElement("li");
      item.className = "rs-" + p.severity;
      item.textContent = p.text;
      item.setAttribute("data-line", String(p.line || ""));
      item.setAttribute("data-col", String(p.col || ""));
      if (p.line) {
        item.tabIndex = 0;
        item.addEventListener("click", function () {
          editor.focus();
          editor.setCursor({ line: p.line - 1, ch: Math.max(0, (p.col || 1) - 1) });
        });
        if (p.severity === "error") {
          var handle = editor.addLineClass(p.line - 1, "background", "rs-bad-line");
          marked.push(handle);
        }
      }
      list.appendChild(item);
    });
    var errors = problems.filter(function (p) { return p.severity === "error"; }).length;
    list.setAttribute("data-errors", String(errors));
    refreshButtons();
    return errors;
  }

  function refreshButtons() {
    var errors = Number($("problems").getAttribute("data-errors") || 0);
    button("run").disabled = !ready || errors > 0 || robotRunning || busy > 0;
    button("run-robot").disabled = !ready || !robotPort || errors > 0 || robotRunning ||
      busy > 0;
    // another robot is connected once this run is over (the run's worker answers no Connect
    // before then)
    Array.prototype.forEach.call(document.querySelectorAll("[data-action=connect]"),
      function (choice) { choice.disabled = !choice.hasAttribute("data-can") || robotRunning; });
  }

  /* Check the editor's text in the worker; an answer to an older text is left unshown. */
  function check() {
    if (!ready) return;
    var mine = ++checked, name = $("name").value, text = editor.getValue();
    written[name] = text;
    call("bridge", "check_text", name, text, $("robot").value).then(function (found) {
      if (mine !== checked) return null;
      var errors = showProblems(JSON.parse(found).problems);
      if (!busy) {
        say(errors ? errors + (errors === 1 ? " error" : " errors") + ": fix it, then run"
                   : "No errors: ready to run");
      }
      return errors ? "" : call("bridge", "diagram_text", name, text);
    }).then(function (svg) {
      if (mine !== checked || svg === null) return;
      var image = $("diagram");
      if (!svg) { image.removeAttribute("src"); return; }
      // an <img> shows the picture and runs nothing in it, whatever names it holds
      image.src = "data:image/svg+xml;charset=utf-8," + encodeURIComponent(svg);
    }).catch(function () {});  // ended by Stop: the fresh worker checks again
  }

  function run() {
    say("Running on the simulator… (■ Stop ends it)");
    busyWith(1);
    var started = performance.now();
    var seed = parseInt($("seed").value, 10) || 0;
    $("result").removeAttribute("data-stopped");
    call("bridge", "run_text", $("name").value, editor.getValue(), $("robot").value,
         $("world").value, seed).then(function (text) {
      var wallS = (performance.now() - started) / 1000;
      var answer = JSON.parse(text), s = showRun(answer);
      if (answer.note) note(answer.note);  // what the record left out, counted
      if (!s) return;
      var factor = wallS > 0 ? s.duration_s / wallS : Infinity;
      document.body.setAttribute("data-real-time-factor", String(factor));
      say("Done: " + s.duration_s.toFixed(1) + " s of robot time in " + wallS.toFixed(1) +
          " s");
    }, function (failure) {
      var text = notAnswered(failure);
      var result = $("result");
      result.removeAttribute("data-outcome");
      result.textContent = text;
      result.setAttribute("data-stopped", text);
    }).then(function () { busyWith(-1); });
  }

  /* The Stop beside Run: a run or a practice grade in the worker ends now, whatever it does. */
  function stopRun() {
    if (!busy) return;
    endPython({ stopped: "Stopped with the Stop button: the run was ended and nothing of " +
                         "it was kept." });
  }

  /* A run's answer in the page (on the simulator or a robot); its summary, or null. */
  function showRun(answer) {
    showProblems(answer.problems);
    var result = $("result"), box = $("viewer");
    box.textContent = "";
    result.removeAttribute("data-outcome");
    if (!answer.summary) {
      result.textContent = answer.error || "The mission has errors: see above.";
      result.setAttribute("data-error", result.textContent);
      say("Not run");
      return null;
    }
    var s = answer.summary;
    result.textContent = s.outcome + ": " + s.mission + " ended in '" + s.final_state +
      "' after " + s.duration_s.toFixed(2) + " s" + (s.reason ? " (" + s.reason + ")" : "");
    result.setAttribute("data-outcome", s.outcome);
    result.setAttribute("data-json", JSON.stringify(s));
    box.innerHTML = answer.viewer;  // roboscript's own block: the run as JSON in a script
    window.roboscriptViewer.mount(box.querySelector(".rs-viewer"));
    return s;
  }

  /* ---- a real robot: the browser's chooser, a run on it, and its stop.
   * The browser gives its USB and Bluetooth objects to the page only, so the page holds the
   * port (robot-port.js) and relays its bytes, in order, to the run, which goes on in the
   * worker like every run (roboscript.transport.webport). The page stops the robot without the
   * worker: once the handshake is done the worker hands it the robot's stop (the driver's own
   * bytes), and Stop, a closing tab, a lost link and a worker that no longer answers while the
   * robot runs make the page write it itself. */
  var SILENT_MS = 2000;  // the worker says it is alive every 250 ms while a run waits
  /* Bytes from the robot handed to the worker since it last said it was alive, at most: a
   * device that floods the line (far past any robot's rate) ends the run, rather than the
   * worker's queue growing while it cannot read. */
  var MAX_UNREAD_BYTES = 1048576;
  var robotPort = null, robotRunning = false, robot = null, chosen = {};
  var portReleased = Promise.resolve(), choosers = { serial: {}, bluetooth: null };

  var SILENT = "The mission's code stopped answering for " + SILENT_MS / 1000 + " s while " +
    "the robot ran (a loop that never ends?), so the page stopped the robot and ended the " +
    "run; nothing of it was kept.";
  var STOPPED_SILENT = "Stopped with the Stop button: the robot was sent its stop at once, " +
    "and the mission's code, which no longer answered (a loop that never ends?), was ended; " +
    "nothing of the run was kept.";
  var FLOODED = "The robot sent more than the run could read (over 1 MB at once: is it the " +
    "robot you chose?), so the page stopped the robot and ended the run; nothing of it was " +
    "kept.";
  var UNPLUGGED = "it was unplugged (or switched off) since you connected it: plug it in " +
    "again, then press its Connect button and choose it";
  var STOPPED_EARLY = "Stopped with the Stop button, before the mission reached the robot: " +
    "nothing of the run was kept.";

  function connectRobot(choice) {
    var name = choice.getAttribute("data-robot"), via = choice.getAttribute("data-via");
    // asked at once, within the click: the browser opens its chooser for a click only
    var asked = via === "bluetooth" ?
      navigator.bluetooth.requestDevice(choosers.bluetooth) :
      navigator.serial.requestPort({ filters: choosers.serial[name] });
    asked.then(function (device) {
      var scheme = via === "bluetooth" ? "webbluetooth" : "webserial";
      return call("connect", "remember", scheme, Object.keys(chosen).length + 1)
        .then(function (url) {
          chosen[url] = { device: device, via: via };
          robotPort = url;
          if (!$("robot").value) $("robot").value = name;
          $("connected").textContent = "Connected: " + choice.textContent + ".";
          document.body.setAttribute("data-robot-port", robotPort);
          check();
        });
    }).catch(function (error) {
      $("connected").textContent = error && error.name === "NotFoundError" ?
        "No robot chosen. Is it plugged in (or switched on, for Bluetooth)? Then try again." :
        "The browser could not connect: " + error;
    });
  }

  function runOnRobot() {
    if (!robotPort || robotRunning || !ready) return;
    var run = robot = { url: robotPort, port: null, stop: null, heard: performance.now(),
                        unread: 0, over: false, closed: false, stopAsked: false,
                        longestSilenceMs: 0 };
    robotRunning = true;
    note("");
    $("result").removeAttribute("data-stopped");
    refreshButtons();
    button("stop").disabled = false;
    say("Connecting to the robot… (Stop stops it at once)");
    document.body.removeAttribute("data-robot-ready");
    var watch = window.setInterval(function () { watchRobot(run); }, 250);
    var seed = parseInt($("seed").value, 10) || 0;
    callWaiting("bridge", "run_text", $("name").value, editor.getValue(), $("robot").value,
                $("world").value, seed, run.url)
      .then(function (text) {
        var answer = JSON.parse(text);
        var s = showRun(answer);
        if (answer.note) note(answer.note);
        var log = $("wire-log");
        if (answer.wire_log) {
          log.href = URL.createObjectURL(new Blob([answer.wire_log], { type: "text/plain" }));
          log.hidden = false;
          document.body.setAttribute("data-wire-log", answer.wire_log);
        }
        if (s) say("Done on the robot: " + s.duration_s.toFixed(1) + " s");
      }, function (failure) {
        var text = notAnswered(failure), result = $("result");
        result.removeAttribute("data-outcome");
        result.textContent = text;
        result.setAttribute("data-stopped", text);
      })
      .then(function () {
        window.clearInterval(watch);
        run.over = true;
        closePort(run);
        robot = null;
        robotRunning = false;
        button("stop").disabled = true;
        refreshButtons();
        check();
      });
  }

  /* What the worker says of the robot's port (roboscript.transport.webport). */
  function fromWorker(message) {
    var run = robot;
    if (!run) return;
    var now = performance.now();
    if (run.port && now - run.heard > run.longestSilenceMs) {
      // how long the worker went without a word while it held the robot (the page's tests
      // and benchmarks read it: how far an honest run stays from SILENT_MS)
      run.longestSilenceMs = now - run.heard;
      document.body.setAttribute("data-robot-longest-silence-ms",
                                 String(Math.round(run.longestSilenceMs)));
    }
    run.heard = now;
    if (message.type === "alive") run.unread = 0;
    else if (message.type === "port-open") openPort(run, message);
    else if (message.type === "port-write" && run.port && !run.over) run.port.write(message.data);
    else if (message.type === "port-close") closePort(run);
    else if (message.type === "robot-ready") {
      // none (a robot whose stop could not be worked out): the page leaves the stop to the run
      run.stop = message.stop && message.stop.length ? message.stop : null;
      document.body.setAttribute("data-robot-ready", "1");
      say("Running the mission on the robot… (Stop stops it at once)");
    }
  }

  function toWorker(event, data) {
    if (worker) worker.postMessage({ type: "port", event: event, data: data });
  }

  function openPort(run, asked) {
    var choice = chosen[asked.url];
    if (!choice) {
      toWorker("failed", "it is no longer connected in this page: press Connect again");
      return;
    }
    var on = {
      received: function (bytes) {
        if (run.over) return;
        run.unread += bytes.length;
        if (run.unread > MAX_UNREAD_BYTES) takeOver(run, FLOODED);
        else toWorker("received", bytes);
      },
      lost: function (detail) { portLost(run, detail); }
    };
    portReleased.then(function () {  // the last run's port, released first
      if (run.over) return null;
      return window.rsRobotPort(choice.device, choice.via, asked, on).catch(function (error) {
        // unplugged and plugged in again, a USB board is a new port for the browser: the
        // one of that kind it lets the page use, if there is exactly one, with no new Connect
        return pluggedAgain(choice).then(function (again) {
          if (!again || run.over) throw error;
          choice.device = again;
          choice.lost = false;
          return window.rsRobotPort(again, choice.via, asked, on);
        });
      });
    }).then(function (port) {
      if (!port) return;
      choice.lost = false;
      run.port = port;
      if (run.over || run.closed) closePort(run);
      else toWorker("opened");
    }, function (error) {
      toWorker("failed", choice.lost ? UNPLUGGED : String(error && error.message || error));
    });
  }

  /* The USB board plugged in again after ``choice`` was unplugged: the one port of the same
   * kind (USB vendor and product) the browser lets this page use, other than the old one;
   * null when there is none, or more than one (the page never guesses between two boards). */
  function pluggedAgain(choice) {
    var old = choice.device;
    if (choice.via !== "serial" || !navigator.serial.getPorts) return Promise.resolve(null);
    var kind = old.getInfo ? old.getInfo() : {};
    return navigator.serial.getPorts().then(function (ports) {
      var same = ports.filter(function (port) {
        var info = port.getInfo ? port.getInfo() : {};
        return port !== old && info.usbVendorId === kind.usbVendorId &&
          info.usbProductId === kind.usbProductId;
      });
      return same.length === 1 ? same[0] : null;
    }, function () { return null; });
  }

  function closePort(run) {
    run.closed = true;
    if (!run.port) return;
    var port = run.port;
    run.port = null;
    portReleased = port.close();
  }

  /* The device went: its stop is written at once (where the line still carries it), and the
   * run ends with the lost link's sentence, from the worker. */
  function portLost(run, detail) {
    if (chosen[run.url]) chosen[run.url].lost = true;
    if (run.over) return;
    if (run.port && run.stop) run.port.stopNow(run.stop);
    toWorker("lost", detail);
  }

  /* The page stops the robot by itself (once): its stop, then the port released. */
  function haltRobot(run) {
    if (run.over) return false;
    run.over = true;
    if (run.port && run.stop) run.port.stopNow(run.stop);
    closePort(run);
    return true;
  }

  /* The page stops the robot by itself and ends the worker, whatever it is doing. */
  function takeOver(run, sentence) {
    if (haltRobot(run)) endPython({ stopped: sentence });
  }

  /* A run whose worker no longer answers while it holds the robot (a loop that never gives
   * the worker back): measured here, on the page's clock. */
  function watchRobot(run) {
    if (run.over || !run.port) return;
    if (performance.now() - run.heard > SILENT_MS) {
      takeOver(run, run.stopAsked ? STOPPED_SILENT : SILENT);
    }
  }

  /* Stop: the robot's stop goes out now, from the page; the run, if its worker answers, ends
   * at its next wait with its record ("stopped with the Stop button"), else watchRobot ends
   * it. A run that has not reached the robot yet is ended at once. */
  function stopRobot(reason) {
    var run = robot;
    if (!run || run.over) return;
    run.stopAsked = true;
    if (!run.port) { takeOver(run, STOPPED_EARLY); return; }
    if (run.stop) run.port.stopNow(run.stop);
    toWorker("interrupt", reason);
  }

  /* A closing tab: the robot's stop is started within this event (no later task runs). */
  function pageClosed() {
    var run = robot;
    if (!run || run.over) return;
    if (run.port && run.stop) run.port.stopNow(run.stop);
    toWorker("interrupt", "the page was closed");
  }

  /* The choosers' filters, from the worker's Python (the page's starts only on Connect). */
  function connectPanel() {
    var robots = {};
    Array.prototype.forEach.call(document.querySelectorAll("[data-action=connect]"),
      function (choice) { robots[choice.getAttribute("data-robot")] = true; });
    return Promise.all(Object.keys(robots).map(function (robot) {
      return call("connect", "serial_filters", robot).then(function (filters) {
        choosers.serial[robot] = JSON.parse(filters);
      });
    }).concat([call("connect", "bluetooth_options").then(function (options) {
      choosers.bluetooth = JSON.parse(options);
    })])).then(connectButtons);
  }

  function connectButtons() {
    var serial = "serial" in navigator, bluetooth = "bluetooth" in navigator;
    var waits = typeof WebAssembly.Suspending === "function";  // JSPI: a run can wait
    Array.prototype.forEach.call(document.querySelectorAll("[data-action=connect]"),
      function (choice) {
        var via = choice.getAttribute("data-via");
        if (waits && (via === "bluetooth" ? bluetooth : serial)) {
          choice.setAttribute("data-can", "1");  // this browser can reach it
        }
        choice.disabled = !choice.hasAttribute("data-can") || robotRunning;
        choice.addEventListener("click", function () { connectRobot(choice); });
      });
    if (!waits && (serial || bluetooth)) {
      $("connected").textContent = "This browser is too old to drive a robot from a page: " +
        "update Chrome or Edge.";
    }
    button("run-robot").addEventListener("click", runOnRobot);
    button("stop").addEventListener("click", function () {
      stopRobot("stopped with the Stop button");
    });
    // Never leave a robot running: a closing or reloading tab sends the stop first.
    window.addEventListener("beforeunload", pageClosed);
    window.addEventListener("pagehide", pageClosed);
  }

  function save() {
    var blob = new Blob([editor.getValue()], { type: "text/plain" });
    var link = document.createElement("a");
    link.href = URL.createObjectURL(blob);
    link.download = $("name").value || "mission.yaml";
    document.body.appendChild(link);
    link.click();
    link.remove();
    kept = editor.getValue();
  }

  // the chooser is asked within the click that said so: a browser opens it for a click only
  function open() { unlessUnsaved("opening a file", function () { $("file").click(); }); }

  var MAX_OPENED_BYTES = 1000000;  // a mission, a world or a profile is a few kB of text

  /* A file the student opened, into the editor, unless it cannot be a mission: too big, or
   * not text. Text not saved as UTF-8 (an old Windows editor) is read as Windows-1252, and
   * said so, rather than losing its accented letters to the replacement character. */
  function opened() {
    var input = $("file"), file = input.files && input.files[0], note = $("file-note");
    if (!file) return;
    input.value = "";
    note.textContent = "";
    note.removeAttribute("data-refused");
    note.removeAttribute("data-opened");
    function refuse(text) {
      note.textContent = text;
      note.setAttribute("data-refused", "1");
      note.setAttribute("data-opened", file.name);  // handled (a test waits for it)
    }
    if (file.size > MAX_OPENED_BYTES) {
      refuse("Not opened: " + file.name + " is " + (file.size / 1e6).toFixed(1) + " MB, far " +
        "too big for a mission (a mission is a few kB of text). Did you pick the right file?");
      return;
    }
    file.arrayBuffer().then(function (buffer) {
      var bytes = new Uint8Array(buffer), text;
      if (bytes.indexOf(0) >= 0) {
        refuse("Not opened: " + file.name + " is not a text file (it holds binary data, " +
          "like a picture or a program). Open a mission: a .yaml or .py file.");
        return;
      }
      try {
        text = new TextDecoder("utf-8", { fatal: true }).decode(bytes);
      } catch (notUtf8) {
        text = new TextDecoder("windows-1252").decode(bytes);
        note.textContent = file.name + " was not saved as UTF-8, so it was read as Western " +
          "(Windows-1252) text: check its accented letters. Save writes it as UTF-8.";
      }
      load(file.name, text);
      note.setAttribute("data-opened", file.name);
    });
  }

  function hardwareNote() {
    var serial = "serial" in navigator, bluetooth = "bluetooth" in navigator;
    var has = serial && bluetooth ? "USB (Web Serial) and Bluetooth (Web Bluetooth)" :
      serial ? "USB (Web Serial) but not Bluetooth" : bluetooth ? "Bluetooth but not USB" : "";
    $("hardware").textContent = has ?
      "This browser can reach robots over " + has + ": connect yours below, then run on " +
      "it. The simulator works here too." :
      "This browser cannot reach a robot over USB or Bluetooth (it has no Web Serial or " +
      "Web Bluetooth). The simulator works here; for a real robot use Chrome or Edge on a " +
      "computer or a Chromebook.";
    document.body.setAttribute("data-web-serial", serial ? "1" : "0");
  }

  function boot() {
    makeEditor();
    hardwareNote();
    button("run").addEventListener("click", run);
    button("stop-run").addEventListener("click", stopRun);
    button("save").addEventListener("click", save);
    button("open").addEventListener("click", open);
    button("keep-edits").addEventListener("click", function () { answerUnsaved(false); });
    button("lose-edits").addEventListener("click", function () { answerUnsaved(true); });
    $("unsaved").addEventListener("cancel", function () { replacing = null; });
    $("file").addEventListener("change", opened);
    startPython().then(function (started) {
      // how much of the start is the runtime itself (tests/bench/bench_web.py reports it)
      document.body.setAttribute("data-runtime-ms", String(Math.round(started.runtimeMs)));
      return connectPanel();
    }).then(function () {
      // the practice grade (grade.js) starts now, with what it needs of the editor; the page
      // is ready once it has read the shipped specs too
      var detail = { call: call, say: say, busy: busyWith, notAnswered: notAnswered, pending: [],
        name: function () { return $("name").value; },
        text: function () { return editor.getValue(); } };
      document.dispatchEvent(new CustomEvent("roboscript-ready", { detail: detail }));
      return Promise.all(detail.pending);
    }).then(function () {
      // from the moment the page started loading, its big scripts (the runtime) included
      var readyMs = Math.round(performance.now());
      document.body.setAttribute("data-ready-ms", String(readyMs));
      document.body.setAttribute("data-ready", "1");
      check();
    }).catch(failedToStart);
  }

  if (document.readyState === "loading") document.addEventListener("DOMContentLoaded", boot);
  else boot();
})();
