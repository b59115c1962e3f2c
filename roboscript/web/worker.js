/* roboscript's Python for the page, in a Web Worker of its own: checking as the student types,
 * runs on the simulator, runs on a real robot and practice grades run here, never in the
 * page's own thread, so a student's code that loops, prints or allocates without end cannot
 * freeze the page; its Stop ends this worker whole and the page starts a fresh one.
 *
 * A run on a robot waits on the robot (Pyodide's callPromising and run_sync), so while it
 * goes on this worker takes the page's messages: the robot's bytes and the page's Stop, for
 * roboscript.transport.webport (the page holds the port and relays its bytes). It also says
 * it is alive every ALIVE_MS while it waits: the page stops the robot by itself, without this
 * worker, when that stops (a student's loop that never gives the worker back). Other calls
 * that come meanwhile (checking as the student types) wait for the run to end.
 *
 * The page makes this worker from text (a file:// page may load no worker script by URL):
 * answered-fetch.js and this part come first in the text, then Pyodide's loader and runtime. Messages:
 *   page -> worker: {type: "boot", assets: {name: base64}, lock, indexURL}
 *                   {type: "call", id, module, fn, args, waits: true for a run on a robot}
 *                   {type: "port", event, data}: the robot's port, see webport.py
 *   worker -> page: {type: "ready", runtimeMs, readyMs} | {type: "failed", error}
 *                   {type: "alive"} while a run on a robot waits; webport.py's port-... and
 *                   robot-ready
 *                   {type: "answer", id, value} | {type: "answer", id, error}, each with
 *                   heapBytes (the Python heap's size now) and outOfMemory: true when
 *                   Python was refused memory during the call
 */
(function () {
  "use strict";

  // Pyodide refuses a classic worker (it would load packages with importScripts, which this
  // app never does), and a file:// page can start no module worker: hide importScripts.
  self.importScripts = undefined;

  var assets = {}, py = null, modules = {}, printed = 0, refused = 0;
  var waiting = null, held = [];  // the run on a robot under way, and the calls that wait for it
  var ALIVE_MS = 250;
  var PRINTED_TO_CONSOLE = 200;  // a flood of print() reaches the run's record, not the console
  var CONSOLE_LINE_CHARS = 500;  // nor does one huge line (the record cuts it there too)

  /* The most memory this worker's Python may have, bytes. Python's heap grows by asking the
   * WebAssembly memory for more pages; a request past this bound is refused at once, so
   * Python raises MemoryError where the student's code asked (a list that grows without end,
   * [0] * 2_000_000_000) after a count of bytes, never after the browser has spent seconds,
   * or the computer's memory, finding out that it cannot have them. Python uses a tenth of it
   * for the biggest practice grade; a Chromebook has 4 GB for everything it runs. */
  var MEMORY_LIMIT_BYTES = 1024 * 1024 * 1024;
  var grow = WebAssembly.Memory.prototype.grow;
  WebAssembly.Memory.prototype.grow = function (pages) {
    if (this.buffer.byteLength + pages * 65536 > MEMORY_LIMIT_BYTES) {
      refused += 1;
      throw new RangeError("the page's Python may have at most " + MEMORY_LIMIT_BYTES +
                           " bytes of memory");
    }
    return grow.call(this, pages);
  };

  // Pyodide's binaries come from what the page handed over (answered-fetch.js, first in
  // this worker's text)
  self.rsAnswerFetch(function () { return assets; });

  function out(line) {
    printed += 1;
    if (printed <= PRINTED_TO_CONSOLE) {
      console.log(line.length > CONSOLE_LINE_CHARS ?
                  line.slice(0, CONSOLE_LINE_CHARS) + "…" : line);
    }
  }

  function boot(message) {
    var started = performance.now();
    assets = message.assets;
    self.rsBaseURI = message.indexURL;
    self.loadPyodide({
      indexURL: message.indexURL,
      createPyodideModule: self.rsCreatePyodide,
      lockFileContents: Promise.resolve(JSON.parse(message.lock)),
      stdout: out,
      stderr: out
    }).then(function (runtime) {
      py = runtime;
      var runtimeMs = performance.now() - started;
      return self.fetch("site-packages.zip").then(function (response) {
        return response.arrayBuffer();
      }).then(function (zip) {
        py.unpackArchive(zip, "zip", { extractDir: "/home/pyodide/site-packages" });
        py.runPython("import sys; sys.path.insert(0, '/home/pyodide/site-packages')");
        modules.bridge = py.pyimport("roboscript.web.bridge");
        modules.connect = py.pyimport("roboscript.web.connect");
        assets = {};  // unpacked: the page's copy is the only one kept
        self.postMessage({ type: "ready", runtimeMs: runtimeMs,
                           readyMs: performance.now() - started });
      });
    }).catch(function (error) {
      self.postMessage({ type: "failed", error: String(error && error.message || error) });
    });
  }

  function failed(answer, error) {
    // a Python error here is a roboscript bug or Python itself out of memory: say which
    answer.error = String(error && error.message || error);
    answer.fatal = !!(py && py._api && py._api.fatal_error_occurred);
  }

  function send(answer) {
    // Python was refused memory in this call: caught as MemoryError (in the student's code,
    // said at its line) or not, the page starts a fresh Python, whose heap is small again
    if (refused) answer.outOfMemory = true;
    answer.heapBytes = py && py._module ? py._module.HEAP8.length : 0;
    self.postMessage(answer);
  }

  function call(message) {
    if (waiting) { held.push(message); return; }  // one Python stack at a time
    var answer = { type: "answer", id: message.id };
    printed = 0;
    refused = 0;
    var module = modules[message.module], fn = module && module[message.fn];
    if (!fn) {  // answered all the same: a caller waits on every answer
      failed(answer, new Error("no function " + message.module + "." + message.fn));
      send(answer);
      return;
    }
    if (!message.waits) {
      try {
        answer.value = fn.apply(null, message.args);
      } catch (error) {
        failed(answer, error);
      }
      send(answer);
      return;
    }
    var alive = self.setInterval(function () { self.postMessage({ type: "alive" }); }, ALIVE_MS);
    waiting = Promise.resolve().then(function () {
      return fn.callPromising.apply(fn, message.args);
    }).then(function (value) { answer.value = value; }, function (error) {
      failed(answer, error);
    }).then(function () {
      self.clearInterval(alive);
      waiting = null;
      send(answer);
      while (held.length && !waiting) call(held.shift());
    });
  }

  self.onmessage = function (event) {
    var message = event.data;
    if (message.type === "boot") boot(message);
    else if (message.type === "call") call(message);
    else if (message.type === "port" && modules.connect) {
      modules.connect.from_page(message.event, message.data);
    }
  };
})();
