// Run roboscript's SPIKE hub agent in MicroPython's WebAssembly port, on stand-ins for the
// SPIKE 3 API (micropython_hub/), driven by a recorded host session.
// Usage: node run_micropython.mjs MICROPYTHON_MJS STANDINS_DIR AGENT(.py|.mpy) SESSION_TXT
import { readFileSync, readdirSync } from "node:fs";
import { basename, join } from "node:path";
import { pathToFileURL } from "node:url";

const [micropython, standins, agent, session] = process.argv.slice(2);
const { loadMicroPython } = await import(pathToFileURL(micropython).href);
const mp = await loadMicroPython({
  stdout: (line) => process.stdout.write(line + "\n"),
  stderr: (line) => process.stdout.write(line + "\n"),
  linebuffer: true,
});
mp.FS.mkdir("/lib");
for (const name of readdirSync(standins)) {
  if (name.endsWith(".py")) mp.FS.writeFile(join("/lib", name), readFileSync(join(standins, name)));
}
const agentName = basename(agent).endsWith(".mpy") ? "hub_agent.mpy" : "hub_agent.py";
mp.FS.writeFile(join("/lib", agentName), readFileSync(agent));
mp.FS.writeFile("/session.txt", readFileSync(session));
try {
  mp.runPython("import sys\nsys.path.insert(0, '/lib')\nimport session_runner");
} catch (error) {
  process.stdout.write("ERROR " + String(error.message).replace(/\n/g, " | ") + "\n");
  process.exitCode = 1;
}
