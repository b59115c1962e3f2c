/* roboscript in a browser tab: what this browser cannot do, said plainly to the student.
 *
 * The simulator, the editor and the practice grade need WebAssembly only, which every current
 * browser has. A real robot needs Web Serial (USB) or Web Bluetooth, which only Chrome, Edge
 * and other Chromium browsers have on computers and Chromebooks (never on an iPad or iPhone,
 * whatever the browser: they all are Safari underneath), in a page that came from a file or
 * https://, not inside a course page that withholds them; and JSPI (WebAssembly JavaScript
 * Promise Integration, Chrome and Edge 137 and later), so Python can wait for the robot.
 * window.rsPlatform() says which of these this browser lacks, one note each, and the notes are
 * shown under the robot note as soon as the page loads, before Python starts.
 */
(function () {
  "use strict";

  var OTHER_BROWSER = "for a real robot use Chrome or Edge on a computer or a Chromebook.";

  function allowedHere(feature) {
    // A course site (an LMS) shows the page in a frame, and only lends it USB and Bluetooth
    // if its frame says so (allow="serial; bluetooth").
    var policy = document.permissionsPolicy || document.featurePolicy;
    if (!policy || typeof policy.allowsFeature !== "function") return true;
    try { return policy.allowsFeature(feature); } catch (error) { return true; }
  }

  function framed() {
    try { return window.self !== window.top; } catch (error) { return true; }
  }

  window.rsPlatform = function () {
    var agent = navigator.userAgent || "";
    var apple = /iPad|iPhone|iPod/.test(agent) ||
      (/Macintosh/.test(agent) && (navigator.maxTouchPoints || 0) > 1);  // an iPad asking
    var firefox = /Firefox\//.test(agent);
    var safari = !apple && /Safari\//.test(agent) && !/Chrom(e|ium)\/|Edg\//.test(agent);
    var wasm = typeof WebAssembly === "object";
    var found = {
      webassembly: wasm,
      serial: "serial" in navigator,
      bluetooth: "bluetooth" in navigator,
      jspi: wasm && typeof WebAssembly.Suspending === "function",
      secure: window.isSecureContext !== false,
      framed: framed(),
      notes: []
    };
    function note(feature, text) { found.notes.push({ feature: feature, text: text }); }

    if (!wasm) {
      note("webassembly", "This browser cannot run Python (it has no WebAssembly), so " +
        "nothing on this page works here: open it in a current Chrome, Edge, Firefox or Safari.");
      return found;
    }
    if (apple) {
      note("ipad", "On an iPad or iPhone no browser can talk to a robot over USB or " +
        "Bluetooth: Apple allows no Web Serial or Web Bluetooth there, not even in Chrome. " +
        "The simulator and the practice grade work here; for a real robot use a Chromebook, " +
        "or a computer with Chrome or Edge.");
      return found;
    }
    if (!found.secure) {
      note("http", "This page came over plain http://, so the browser keeps USB and " +
        "Bluetooth away from it. The simulator works; for a real robot ask your teacher " +
        "for an https:// link, or save the page's folder and open index.html from it.");
      return found;
    }
    if (!found.serial && !found.bluetooth) {
      var which = firefox ? "Firefox" : safari ? "Safari" : "This browser";
      note(firefox ? "firefox" : safari ? "safari" : "serial", which + " cannot talk to a " +
        "robot over USB or Bluetooth (it has no Web Serial or Web Bluetooth). The simulator " +
        "and the practice grade work here; " + OTHER_BROWSER);
      return found;
    }
    if (!found.serial) {
      note("serial", "This browser cannot talk to a robot over a USB cable (it has no Web " +
        "Serial): a SPIKE hub over Bluetooth works; for MIRTO, StackMod or PLEN2 use Chrome " +
        "or Edge on a computer or a Chromebook.");
    }
    if (!found.bluetooth) {
      note("bluetooth", "This browser cannot talk to a robot over Bluetooth (it has no Web " +
        "Bluetooth; on Linux, Chrome has it only when turned on in chrome://flags): plug " +
        "the robot in with a USB cable instead.");
    }
    if (!found.jspi) {
      note("jspi", "This browser is too old to drive a robot from Python in a page (it lacks " +
        "JSPI, which lets Python wait for the robot): update Chrome or Edge to version 137 " +
        "or later. The simulator works here.");
    }
    if (found.framed && !(allowedHere("serial") || allowedHere("bluetooth"))) {
      note("frame", "This page is shown inside another page (your course site), which " +
        "does not let it use USB or Bluetooth: open it in a tab of its own to drive a robot.");
    }
    return found;
  };

  function show() {
    var list = document.querySelector("[data-role='platform']");
    if (!list) return;
    var found = window.rsPlatform();
    list.textContent = "";
    found.notes.forEach(function (n) {
      var item = document.createElement("li");
      item.setAttribute("data-feature", n.feature);
      item.textContent = n.text;
      list.appendChild(item);
    });
    document.body.setAttribute("data-platform-notes",
      found.notes.map(function (n) { return n.feature; }).join(" "));
  }

  if (document.readyState === "loading") document.addEventListener("DOMContentLoaded", show);
  else show();
})();
