/* The robot's port in the page: the SerialPort (Web Serial) or BluetoothDevice (Web Bluetooth)
 * the student chose lives here, never in a worker (Web Bluetooth exists in no worker). The run
 * goes on in the page's worker (roboscript.transport.webport): this moves the bytes between
 * the device and the worker, in order, and lets the page stop the robot by itself.
 *
 * window.rsRobotPort(device, via, options, on): via is "serial" or "bluetooth"; options are
 * what the worker asked with (baudRate; bluetooth: {service, rx, tx}); on.received(bytes) and
 * on.lost(detail) say what the device did. Returns a promise of the open port:
 *   write(bytes)       after what was written before (a Bluetooth write is one packet)
 *   stopNow(packets)   drop the writes not gone yet and write these first (the robot's stop):
 *                      from then on the port takes no other write
 *   close()            a promise, settled once the writes under way went (or CLOSE_WAIT_MS
 *                      passed) and the device is released
 *   queuedBytes()      bytes handed to the browser and not taken yet
 */
(function () {
  "use strict";

  /* Bytes waiting for the device, at most: a device that takes nothing more (a hung USB
   * adapter) makes the run end as a lost link, rather than the page keeping all it is sent. */
  var MAX_QUEUED_BYTES = 65536;
  var CLOSE_WAIT_MS = 2000;  // a device that takes nothing more must not keep the port open

  function errorText(error) {
    var text = String(error && error.message || error || "").trim();
    return text.split("\n").pop();
  }

  window.rsRobotPort = function (device, via, options, on) {
    var queue = [], queued = 0, sending = false, stopped = false, closing = null;
    var gone = false, failed = false;
    var writer = null, reader = null, rx = null, tx = null, listening = [];

    function listen(target, type, handler) {
      target.addEventListener(type, handler);
      listening.push([target, type, handler]);
    }

    /* The device went (unplugged, out of reach) or a write failed: said once. A line whose
     * reading ended may still carry writes (the stop): only a failed write ends them. */
    function lost(detail, writesFailed) {
      if (writesFailed) {
        failed = true;
        queue = [];
        queued = 0;
      }
      if (gone || closing) return;
      gone = true;
      on.lost(detail || "");
    }

    function startWrite(packet) {
      return via === "bluetooth" ? rx.writeValueWithoutResponse(packet) : writer.write(packet);
    }

    function sendNext() {
      if (!queue.length || failed) { sending = false; return; }
      sending = true;
      var packet = queue.shift();
      var written;
      try {
        written = startWrite(packet);
      } catch (error) {
        sending = false;
        lost(errorText(error), true);
        return;
      }
      written.then(function () {
        queued -= packet.length;
        sendNext();
      }, function (error) {
        sending = false;
        lost(errorText(error), true);
      });
    }

    function write(packet) {
      if (failed || stopped) return;
      queue.push(packet);
      queued += packet.length;
      if (queued > MAX_QUEUED_BYTES) {
        lost("the robot took no more bytes (" + queued + " were waiting)", true);
        return;
      }
      if (!sending) sendNext();
    }

    function stopNow(packets) {
      if (stopped || failed) return;
      stopped = true;
      queue.forEach(function (packet) { queued -= packet.length; });
      queue = [];
      if (via === "bluetooth") {  // one GATT write at a time: next after the one under way
        queue = packets.slice();
        packets.forEach(function (packet) { queued += packet.length; });
        if (!sending) sendNext();
        return;
      }
      // handed to the stream now, within the caller's task (a closing tab runs no later
      // one): the stream keeps them after the write under way
      packets.forEach(function (packet) {
        queued += packet.length;
        writer.write(packet).then(function () { queued -= packet.length; },
                                  function (error) { lost(errorText(error), true); });
      });
    }

    function readSerial() {
      if (closing || !device.readable) { lost(""); return; }
      reader = device.readable.getReader();
      function next() {
        return reader.read().then(function (result) {
          if (result.done) return null;
          on.received(result.value);
          return next();
        });
      }
      // a framing error, a break or an overrun ends one stream, and the port gives a new one
      next().catch(function () {}).then(function () {
        try { reader.releaseLock(); } catch (error) { /* a port already gone */ }
        reader = null;
        readSerial();
      });
    }

    function notified(event) {
      var view = event.target.value;  // a DataView on the notification's bytes
      on.received(new Uint8Array(view.buffer.slice(view.byteOffset,
                                                   view.byteOffset + view.byteLength)));
    }

    function opened() {
      if (via === "bluetooth") {
        var service = options.bluetooth;
        return device.gatt.connect().then(function (server) {
          return server.getPrimaryService(service.service);
        }).then(function (found) {
          return Promise.all([found.getCharacteristic(service.rx),
                              found.getCharacteristic(service.tx)]);
        }).then(function (both) {
          rx = both[0];
          tx = both[1];
          listen(tx, "characteristicvaluechanged", notified);
          listen(device, "gattserverdisconnected", function () { lost(""); });
          return tx.startNotifications();
        });
      }
      return device.open({ baudRate: options.baudRate }).then(function () {
        writer = device.writable.getWriter();
        listen(device, "disconnect", function () { lost(""); });
        readSerial();
      });
    }

    function shut() {
      listening.forEach(function (entry) { entry[0].removeEventListener(entry[1], entry[2]); });
      listening = [];
      if (via === "bluetooth") {
        if (device.gatt.connected) device.gatt.disconnect();
        return Promise.resolve();
      }
      var released = writer ? writer.close().catch(function () {}) : Promise.resolve();
      return released.then(function () {
        return reader ? reader.cancel().catch(function () {}) : null;
      }).then(function () { return device.close(); }).catch(function () {});
    }

    function close() {
      if (closing) return closing;
      var giveUp = performance.now() + CLOSE_WAIT_MS;
      closing = new Promise(function (resolve) {
        (function drained() {
          if (sending && !failed && performance.now() < giveUp) window.setTimeout(drained, 5);
          else resolve();
        })();
      }).then(function () {
        // a device gone for good may never answer its close: the next run must not wait
        return Promise.race([shut(), new Promise(function (resolve) {
          window.setTimeout(resolve, CLOSE_WAIT_MS);
        })]);
      });
      return closing;
    }

    return opened().then(function () {
      return {
        write: write, stopNow: stopNow, close: close,
        queuedBytes: function () { return queued; }
      };
    });
  };
})();
