// The live view's end-to-end check (docs/visualization.md): a Foxglove WebSocket client
// (@foxglove/ws-protocol's FoxgloveClient over `ws`, as Foxglove itself speaks it) connects to
// a mission run with --live, checks the advertised channels (topics and schema names),
// subscribes to all of them, and checks that the first message of each of the pose, path,
// tour, mesh, ISE, image and transform channels arrives and decodes as JSON with the fields
// its schema requires at the top level. Exits 0 printing "live_client: ok", else 1 with why.
//
//   node live_client.mjs ws://localhost:8765              (a running mission)
//   node live_client.mjs SCANCREW LAUNCH OUT [ARGS...]     (starts `SCANCREW run LAUNCH --out
//        OUT --live 0 ARGS...`, reads the port from its log, stops it with SIGINT at the end)
import { spawn } from "node:child_process";
import wsProtocol from "@foxglove/ws-protocol";
import WebSocket from "ws";

const { FoxgloveClient } = wsProtocol;

const TOTAL_MS = 90_000; // everything, mission start included
const CONNECT_MS = 30_000; // retrying the connection
// the channels a one-robot mission (r1) serves, by what they show
const EXPECTED = {
  pose: { topic: "/r1/pose_gt", schema: "foxglove.PoseInFrame" },
  path: { topic: "/r1/pose_gt/path", schema: "foxglove.PosesInFrame" },
  tour: { topic: "/r1/tour", schema: "foxglove.PosesInFrame" },
  mesh: { topic: "/r1/mesh", schema: "foxglove.SceneUpdate" },
  ises: { topic: "/r1/ises", schema: "foxglove.SceneUpdate" },
  image: { topic: "/r1/depth", schema: "foxglove.RawImage" },
  transforms: { topic: "/tf", schema: "foxglove.FrameTransforms" },
};
const ALSO_ADVERTISED = ["/r1/clusters", "/r1/viewpoints", "/r1/local_path"];

let mission = null;
const started = Date.now();

let done = false;

function finish(code, message) {
  if (done) return;
  done = true;
  console.log(`live_client: ${message}`);
  if (mission && mission.exitCode === null && mission.signalCode === null) {
    mission.kill("SIGINT");
    const hard = setTimeout(() => mission.kill("SIGKILL"), 20_000);
    mission.on("exit", () => {
      clearTimeout(hard);
      process.exit(code);
    });
  } else {
    process.exit(code);
  }
}

setTimeout(() => finish(1, `FAILED: not done after ${TOTAL_MS / 1000} s`), TOTAL_MS).unref();

// Starts the mission; resolves with its live view's URL (from its log).
function startMission([bin, launch, out, ...rest]) {
  return new Promise((resolve, reject) => {
    mission = spawn(bin, ["run", launch, "--out", out, ...rest, "--live", "0"], {
      stdio: ["ignore", "ignore", "pipe"],
    });
    let log = "";
    mission.stderr.on("data", (chunk) => {
      log += chunk.toString();
      const m = log.match(/live view: (ws:\/\/[^\s]+)/);
      if (m) resolve(m[1]);
    });
    mission.on("exit", (code) => {
      const why = `the mission exited (${code}) before every channel was seen:\n${log}`;
      reject(new Error(why));
      finish(1, `FAILED: ${why}`);
    });
  });
}

// Connects, retrying until CONNECT_MS; the client is made with the socket, before it opens,
// so that no message of the server's first packet is missed.
function connect(url) {
  const ws = new WebSocket(url, [FoxgloveClient.SUPPORTED_SUBPROTOCOL]);
  let opened = false;
  ws.once("open", () => (opened = true));
  ws.once("error", (e) => {
    if (opened) return;
    if (Date.now() - started > CONNECT_MS) finish(1, `FAILED: cannot connect to ${url}: ${e.message}`);
    else setTimeout(() => connect(url), 250);
  });
  check(url, ws, () => opened);
}

function check(url, ws, opened) {
  const client = new FoxgloveClient({ ws });
  const byId = new Map(); // channel id → channel
  const kindOf = new Map(); // subscription id → expected kind
  const channelOf = new Map(); // subscription id → channel
  const seen = new Set();
  let serverInfo = false;
  client.on("serverInfo", () => (serverInfo = true));
  client.on("status", (s) => console.log(`live_client: server status ${s.level}: ${s.message}`));
  client.on("error", (e) => opened() && finish(1, `FAILED: ${e.message ?? e}`));
  client.on("close", () => {
    const missing = Object.keys(EXPECTED).filter((k) => !seen.has(k));
    if (opened() && missing.length) finish(1, `FAILED: the server closed; no message yet on ${missing}`);
  });
  client.on("advertise", (channels) => {
    if (!serverInfo) return finish(1, "FAILED: advertise before serverInfo");
    for (const c of channels) byId.set(c.id, c);
    const topics = new Map([...byId.values()].map((c) => [c.topic, c]));
    for (const [kind, want] of Object.entries(EXPECTED)) {
      const c = topics.get(want.topic);
      if (!c) return finish(1, `FAILED: no ${kind} channel ${want.topic}; got ${[...topics.keys()]}`);
      if (c.schemaName !== want.schema || c.encoding !== "json" || c.schemaEncoding !== "jsonschema")
        return finish(1, `FAILED: ${want.topic}: ${c.schemaName} ${c.encoding} ${c.schemaEncoding}`);
      JSON.parse(c.schema); // the schema itself is JSON
    }
    for (const t of ALSO_ADVERTISED)
      if (!topics.has(t)) return finish(1, `FAILED: ${t} not advertised`);
    for (const c of channels) {
      const id = client.subscribe(c.id);
      channelOf.set(id, c);
      const kind = Object.entries(EXPECTED).find(([, w]) => w.topic === c.topic);
      if (kind) kindOf.set(id, kind[0]);
    }
    console.log(`live_client: ${url}: ${channels.length} channels advertised, all subscribed`);
  });
  client.on("message", ({ subscriptionId, timestamp, data }) => {
    const channel = channelOf.get(subscriptionId);
    if (!channel) return finish(1, `FAILED: message for unknown subscription ${subscriptionId}`);
    let message;
    try {
      message = JSON.parse(new TextDecoder().decode(data));
    } catch (e) {
      return finish(1, `FAILED: ${channel.topic}: not JSON: ${e.message}`);
    }
    const required = JSON.parse(channel.schema).required ?? [];
    const missing = required.filter((k) => !(k in message));
    if (missing.length) return finish(1, `FAILED: ${channel.topic}: lacks ${missing}`);
    const kind = kindOf.get(subscriptionId);
    if (kind && !seen.has(kind)) {
      seen.add(kind);
      console.log(`live_client: first ${kind} (${channel.topic}) at t ${Number(timestamp) / 1e9} s`);
      if (seen.size === Object.keys(EXPECTED).length)
        finish(0, `ok: ${seen.size} channels decoded in ${(Date.now() - started) / 1000} s`);
    }
  });
}

const args = process.argv.slice(2);
if (args.length === 0) finish(1, "usage: live_client.mjs ws://HOST:PORT | SCANCREW LAUNCH OUT [ARGS]");
try {
  const url = args[0].startsWith("ws://") ? args[0] : await startMission(args);
  connect(url);
} catch (e) {
  finish(1, `FAILED: ${e.message}`);
}
