// Compiles the browser app's Python to bytecode with the Pyodide it ships (bytecode belongs to
// one Python version): roboscript/web/bytecode.py's compile_zip, run inside that Pyodide.
//
//   node compile.mjs PYODIDE_DIR BYTECODE_PY (IN.zip OUT.zip beside|alone)...
import fs from "node:fs";
import path from "node:path";
import { pathToFileURL } from "node:url";

const [runtime, module, ...jobs] = process.argv.slice(2);
const { loadPyodide } = await import(pathToFileURL(path.join(runtime, "pyodide.mjs")).href);
const py = await loadPyodide({ indexURL: runtime + path.sep });
py.runPython(fs.readFileSync(module, "utf8"));
for (let i = 0; i + 2 < jobs.length; i += 3) {
  py.FS.writeFile("/tmp/in.zip", new Uint8Array(fs.readFileSync(jobs[i])));
  py.runPython(
    "with open('/tmp/in.zip', 'rb') as f:\n" +
    "    data = compile_zip(f.read(), beside_source=" + (jobs[i + 2] === "beside" ? "True" : "False") + ")\n" +
    "with open('/tmp/out.zip', 'wb') as f:\n" +
    "    f.write(data)\n"
  );
  fs.writeFileSync(jobs[i + 1], py.FS.readFile("/tmp/out.zip"));
}
