/* Pyodide asks for its binaries with fetch(). A file:// page may not fetch files, and a worker
 * made from text may fetch no file of the page's folder, so both answer those requests from
 * the base64 the asset scripts stored (decoded by the browser itself). The one copy of this
 * rule: the page loads this file as a script, and the build puts it first in the worker's text.
 *
 * self.rsAnswerFetch(assets): from now on, fetch() of a file named in assets() (an object
 * {name: base64}, asked at each request) is answered from there; any other goes on as usual.
 */
(function () {
  "use strict";

  self.rsAnswerFetch = function (assets) {
    var realFetch = self.fetch;
    self.fetch = function (url) {
      var name = String(url).split("/").pop().split("?")[0];
      var data = assets()[name];
      if (data === undefined) return realFetch.apply(this, arguments);
      var type = /\.wasm$/.test(name) ? "application/wasm" : "application/octet-stream";
      return realFetch("data:" + type + ";base64," + data).then(function (response) {
        return response.arrayBuffer();
      }).then(function (bytes) {
        return new Response(bytes, { headers: { "Content-Type": type } });
      });
    };
  };
})();
