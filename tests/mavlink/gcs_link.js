// The GCS side of a MAVLink link for the test clients, on npm's node-mavlink (an implementation
// independent of ours): a UDP socket on 14550 as QGroundControl listens, frames parsed by
// node-mavlink and each received signature checked with the key of the passphrase, frames sent
// signed with strictly increasing timestamps, waits on messages, and the checks' report.
'use strict';
const dgram = require('dgram');
const { PassThrough } = require('stream');
const {
  MavLinkPacketSplitter, MavLinkPacketParser, MavLinkProtocolV2, MavLinkPacketSignature, minimal, standard, common,
} = require('node-mavlink');

const args = {};
for (let i = 2; i < process.argv.length; i += 2) args[process.argv[i].replace(/^--/, '')] = process.argv[i + 1];
const key = MavLinkPacketSignature.key(args.passphrase);
const wrongKey = MavLinkPacketSignature.key(args.passphrase + ' (not it)');
const REGISTRY = { ...minimal.REGISTRY, ...standard.REGISTRY, ...common.REGISTRY };
const GCS_SYSID = 255, GCS_COMPID = 190;

// ---- the link ----
const socket = dgram.createSocket('udp4');
const input = new PassThrough();
let vehicleAddress = null;
socket.on('message', (msg, rinfo) => { if (!args.connect) vehicleAddress = rinfo; input.write(msg); });
const report = { frames: 0, unsigned: 0, bad_signature: 0, by_message: {}, statustexts: [], checks: [] };
const listeners = new Set();
const chunks = new Map();  // STATUSTEXT id -> the text so far
input.pipe(new MavLinkPacketSplitter()).pipe(new MavLinkPacketParser()).on('data', (packet) => {
  report.frames++;
  if (!packet.signature) report.unsigned++;
  else if (!packet.signature.matches(key)) report.bad_signature++;
  const clazz = REGISTRY[packet.header.msgid];
  if (!clazz) return;
  const data = packet.protocol.data(packet.payload, clazz);
  report.by_message[clazz.MSG_NAME] = (report.by_message[clazz.MSG_NAME] || 0) + 1;
  if (clazz.MSG_NAME === 'STATUSTEXT') {
    // Chunks of one text share an id; a chunk shorter than 50 characters is the last.
    const text = (chunks.get(data.id) || '') + data.text;
    if (data.id !== 0 && data.text.length === 50) chunks.set(data.id, text);
    else {
      chunks.delete(data.id);
      report.statustexts.push(text);
      console.log(`  vehicle says: ${text}`);
    }
  }
  for (const l of [...listeners]) l(clazz.MSG_NAME, data, packet);
});

let seq = 0;
let lastTimestampMs = 0;
const sent = [];  // every signed frame, for the replay check
function frame(message, signingKey = key, { signed = true } = {}) {
  const protocol = new MavLinkProtocolV2(GCS_SYSID, GCS_COMPID, signed ? MavLinkProtocolV2.IFLAG_SIGNED : 0);
  const buffer = protocol.serialize(message, seq++ & 255);
  if (!signed) return buffer;
  // Strictly increasing timestamps (the specification asks it of a sender; node-mavlink's
  // default, Date.now(), repeats within a millisecond).
  lastTimestampMs = Math.max(Date.now(), lastTimestampMs + 1);
  return protocol.sign(buffer, 1, signingKey, lastTimestampMs);
}
function sendRaw(buffer) {
  if (!vehicleAddress) throw new Error('no vehicle address yet');
  socket.send(buffer, vehicleAddress.port, vehicleAddress.address);
}
function send(message, options) {
  const b = frame(message, options && options.key ? options.key : key, options);
  sent.push(b);
  sendRaw(b);
}

// Resolves with the first message `name` for which `pred` holds; rejects after `ms`.
function waitFor(name, pred, ms, what) {
  return new Promise((resolve, reject) => {
    const timer = setTimeout(() => { listeners.delete(l); reject(new Error(`timed out after ${ms} ms waiting for ${what || name}`)); }, ms);
    const l = (n, d, p) => {
      if (n !== name || (pred && !pred(d, p))) return;
      clearTimeout(timer);
      listeners.delete(l);
      resolve(d);
    };
    listeners.add(l);
  });
}
// Collects messages `name` for `ms`.
function collect(name, ms, pred) {
  return new Promise((resolve) => {
    const got = [];
    const l = (n, d) => { if (n === name && (!pred || pred(d))) got.push(d); };
    listeners.add(l);
    setTimeout(() => { listeners.delete(l); resolve(got); }, ms);
  });
}
const sleep = (ms) => new Promise((r) => setTimeout(r, ms));
const started = Date.now();
function check(ok, text) {
  report.checks.push({ ok: !!ok, text });
  console.log(`${ok ? 'ok  ' : 'FAIL'} [${((Date.now() - started) / 1000).toFixed(1).padStart(6)} s] ${text}`);
  if (!ok) process.exitCode = 1;
}

let target = 1;
function commandLong(command, params = [], targetComponent = 1) {
  const c = new common.CommandLong();
  c.targetSystem = target;
  c.targetComponent = targetComponent;
  c.command = command;
  c.confirmation = 0;
  for (let i = 0; i < 7; i++) c[`_param${i + 1}`] = params[i] === undefined ? 0 : params[i];
  return c;
}
// Sends a command and waits for its final COMMAND_ACK (IN_PROGRESS ones are progress).
async function command(command, params, ms = 5000, targetComponent = 1) {
  const progress = [];
  const onAck = (n, d) => { if (n === 'COMMAND_ACK' && d.command === command && d.result === 5) progress.push(d.progress); };
  listeners.add(onAck);
  const done = waitFor('COMMAND_ACK', (d) => d.command === command && d.result !== 5, ms, `COMMAND_ACK of ${command}`);
  send(commandLong(command, params, targetComponent));
  try {
    const ack = await done;
    return { result: ack.result, progress };
  } finally {
    listeners.delete(onAck);
  }
}
// Waits for the first ack of a command that may stay in progress (a mission runs for minutes).
async function commandStarted(command, params, ms = 5000) {
  const ack = waitFor('COMMAND_ACK', (d) => d.command === command, ms, `COMMAND_ACK of ${command}`);
  send(commandLong(command, params));
  return (await ack).result;
}


// Listens on `port` as QGroundControl does (the vehicle sends first), or with --connect HOST:PORT
// speaks first to a vehicle that listens (uav-onboard --mavlink udpin:PORT).
async function listen(port) {
  if (args.connect) {
    const [address, p] = args.connect.split(':');
    vehicleAddress = { address, port: Number(p) };
    await new Promise((r) => socket.bind(0, '127.0.0.1', r));
    return;
  }
  await new Promise((r) => socket.bind(port, '127.0.0.1', r));
}
function setTarget(t) { target = t; }
// A GCS heartbeat a second (MAV_TYPE_GCS), as QGroundControl sends: the vehicle's link-loss input.
function startHeartbeat() {
  return setInterval(() => {
    const h = new minimal.Heartbeat();
    h.type = 6; h.autopilot = 8; h.baseMode = 0; h.customMode = 0; h.systemStatus = 4; h.mavlinkVersion = 3;
    send(h);
  }, 1000);
}

module.exports = {
  args, key, wrongKey, report, listeners, frame, sendRaw, send, sent, waitFor, collect, sleep, check, commandLong,
  command, commandStarted, listen, setTarget, startHeartbeat, minimal, standard, common,
};
