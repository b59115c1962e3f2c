/* roboscript in a browser tab: the editor, check as you type, a run on the simulator, the
 * replay and the state diagram, all from roboscript itself running in Pyodide. Works from
 * file:// with no network: every binary comes from the page's own scripts (window.rsAssets).
 */
(function () {
  "use strict";

  function $(role) { return document.querySelector("[data-role='" + role + "']"); }
  function button(action) { return document.querySelector("[data-action='" + action + "']"); }
  function say(text) { $("status").textContent = text; }

  /* Pyodide asks for its binaries with fetch(); a file:// page may not fetch files, so they
   * are answered from the base64 the asset scripts stored (decoded by the browser itself). */
  var realFetch = window.fetch;
  window.fetch = function (url, options) {
    var name = String(url).split("/").pop().split("?")[0];
    var data = (window.rsAssets || {})[name];
    if (data === undefined) return realFetch.apply(this, arguments);
    var type = /\.wasm$/.test(name) ? "application/wasm" : "application/octet-stream";
    return realFetch("data:" + type + ";base64," + data).then(function (response) {
      return response.arrayBuffer();
    }).then(function (bytes) {
      return new Response(bytes, { headers: { "Content-Type": type } });
    });
  };

  var py = null, bridge = null, editor = null, checkTimer = null, marked = [];

  function mode(name) { return /\.py$/.test(name) ? "python" : "yaml"; }

  function makeEditor() {
    var first = window.rsExamples["hello.yaml"] || "";
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
      if (!examples.value) return;
      load(examples.value, window.rsExamples[examples.value]);
      examples.value = "";
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
    button("run").disabled = py === null || errors > 0 || robotRunning;
    button("run-robot").disabled = !robotPort || errors > 0 || robotRunning;
    return errors;
  }

  function call(fn) {
    var args = Array.prototype.slice.call(arguments, 1);
    return JSON.parse(bridge[fn].apply(null, args));
  }

  function check() {
    if (!bridge) return;
    var found = call("check_text", $("name").value, editor.getValue(), $("robot").value);
    var errors = showProblems(found.problems);
    say(errors ? errors + (errors === 1 ? " error" : " errors") + ": fix it, then run"
               : "No errors: ready to run");
    drawDiagram(errors);
  }

  function drawDiagram(errors) {
    var image = $("diagram");
    var svg = errors ? "" : bridge.diagram_text($("name").value, editor.getValue());
    if (!svg) { image.removeAttribute("src"); return; }
    // an <img> shows the picture and runs nothing in it, whatever names it holds
    image.src = "data:image/svg+xml;charset=utf-8," + encodeURIComponent(svg);
  }

  function run() {
    say("Running on the simulator…");
    button("run").disabled = true;
    window.setTimeout(function () {  // let the page say so before the run holds the tab
      var started = performance.now();
      var seed = parseInt($("seed").value, 10) || 0;
      var answer = call("run_text", $("name").value, editor.getValue(), $("robot").value,
                        $("world").value, seed);
      var wallS = (performance.now() - started) / 1000;
      var s = showRun(answer);
      if (!s) return;
      var factor = wallS > 0 ? s.duration_s / wallS : Infinity;
      document.body.setAttribute("data-real-time-factor", String(factor));
      say("Done: " + s.duration_s.toFixed(1) + " s of robot time in " + wallS.toFixed(1) +
          " s");
    }, 20);
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

  /* ---- a real robot: the browser's chooser, a run on it, and its stop (roboscript.web.connect).
   * The run waits on the robot with Pyodide's run_sync, so it is called with callPromising;
   * while it waits the page stays alive, and Stop or closing the tab send the stop at once. */
  var robotPort = null, robotRunning = false, connectPy = null;

  function connectRobot(choice) {
    var robot = choice.getAttribute("data-robot"), via = choice.getAttribute("data-via");
    var asked = via === "bluetooth" ?
      navigator.bluetooth.requestDevice(JSON.parse(connectPy.bluetooth_options())) :
      navigator.serial.requestPort({ filters: JSON.parse(connectPy.serial_filters(robot)) });
    asked.then(function (device) {
      robotPort = connectPy.remember(via === "bluetooth" ? "webbluetooth" : "webserial", device);
      if (!$("robot").value) $("robot").value = robot;
      $("connected").textContent = "Connected: " + choice.textContent + ".";
      document.body.setAttribute("data-robot-port", robotPort);
      check();
    }).catch(function (error) {
      $("connected").textContent = error && error.name === "NotFoundError" ?
        "No robot chosen. Is it plugged in (or switched on, for Bluetooth)? Then try again." :
        "The browser could not connect: " + error;
    });
  }

  function runOnRobot() {
    if (!robotPort) return;
    robotRunning = true;
    button("run-robot").disabled = true;
    button("run").disabled = true;
    button("stop").disabled = false;
    say("Connecting to the robot… (Stop stops it at once)");
    var seed = parseInt($("seed").value, 10) || 0;
    var watch = window.setInterval(function () {  // the handshake done: the mission runs
      if (!connectPy.robot_ready()) return;
      document.body.setAttribute("data-robot-ready", "1");
      say("Running the mission on the robot… (Stop stops it at once)");
      window.clearInterval(watch);
    }, 200);
    document.body.removeAttribute("data-robot-ready");
    bridge.run_text.callPromising($("name").value, editor.getValue(), $("robot").value,
                                  $("world").value, seed, robotPort)
      .then(function (text) {
        var answer = JSON.parse(text);
        var s = showRun(answer);
        var log = $("wire-log");
        if (answer.wire_log) {
          log.href = URL.createObjectURL(new Blob([answer.wire_log], { type: "text/plain" }));
          log.hidden = false;
          document.body.setAttribute("data-wire-log", answer.wire_log);
        }
        if (s) say("Done on the robot: " + s.duration_s.toFixed(1) + " s");
      })
      .catch(function (error) {
        $("result").textContent = "roboscript stopped unexpectedly: " + error;
        say("Not run");
      })
      .then(function () {
        window.clearInterval(watch);
        robotRunning = false;
        button("stop").disabled = true;
        check();
      });
  }

  function stopRobot(reason) {
    if (robotRunning && connectPy) connectPy.stop_robot(reason);
  }

  function connectPanel() {
    connectPy = py.pyimport("roboscript.web.connect");
    var serial = "serial" in navigator, bluetooth = "bluetooth" in navigator;
    var waits = typeof WebAssembly.Suspending === "function";  // JSPI: a run can wait
    Array.prototype.forEach.call(document.querySelectorAll("[data-action=connect]"),
      function (choice) {
        var via = choice.getAttribute("data-via");
        choice.disabled = !waits || !(via === "bluetooth" ? bluetooth : serial);
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
    window.addEventListener("beforeunload", function () { stopRobot("the page was closed"); });
    window.addEventListener("pagehide", function () { stopRobot("the page was closed"); });
  }

  function save() {
    var blob = new Blob([editor.getValue()], { type: "text/plain" });
    var link = document.createElement("a");
    link.href = URL.createObjectURL(blob);
    link.download = $("name").value || "mission.yaml";
    document.body.appendChild(link);
    link.click();
    link.remove();
  }

  function open() {
    var input = $("file");
    input.onchange = function () {
      var file = input.files && input.files[0];
      if (!file) return;
      file.text().then(function (text) { load(file.name, text); });
      input.value = "";
    };
    input.click();
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
    button("save").addEventListener("click", save);
    button("open").addEventListener("click", open);
    window.loadPyodide({
      indexURL: new URL("roboscript-web/", document.baseURI).href,
      createPyodideModule: window.rsCreatePyodide,
      lockFileContents: Promise.resolve(JSON.parse(window.rsPyodideLock)),
      stdout: function (line) { console.log(line); },
      stderr: function (line) { console.log(line); }
    }).then(function (runtime) {
      py = runtime;
      // how much of the start is the runtime itself (tests/bench/bench_web.py reports it)
      document.body.setAttribute("data-runtime-ms", String(Math.round(performance.now())));
      return window.fetch("site-packages.zip");
    }).then(function (response) {
      return response.arrayBuffer();
    }).then(function (zip) {
      py.unpackArchive(zip, "zip", { extractDir: "/home/pyodide/site-packages" });
      py.runPython("import sys; sys.path.insert(0, '/home/pyodide/site-packages')");
      bridge = py.pyimport("roboscript.web.bridge");
      connectPanel();
      // from the moment the page started loading, its big scripts (the runtime) included
      var readyMs = Math.round(performance.now());
      document.body.setAttribute("data-ready-ms", String(readyMs));
      document.body.setAttribute("data-ready", "1");
      check();
      // the practice grade (grade.js) starts now, with what it needs of the editor
      document.dispatchEvent(new CustomEvent("roboscript-ready", { detail: {
        bridge: bridge, say: say,
        name: function () { return $("name").value; },
        text: function () { return editor.getValue(); }
      } }));
    }).catch(function (error) {
      say("roboscript could not start in this browser: " + error);
      document.body.setAttribute("data-ready", "error");
    });
  }

  if (document.readyState === "loading") document.addEventListener("DOMContentLoaded", boot);
  else boot();
})();
