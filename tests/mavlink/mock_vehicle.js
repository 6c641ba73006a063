// A mock MAVLink vehicle on npm's node-mavlink (independent of our codec), behaving as PX4 or
// ArduPilot document their services, for our GCS to fly:
//   - HEARTBEAT with the autopilot's id, vehicle type and custom modes (PX4: main/sub mode in
//     bits 16-31; ArduCopter/ArduPlane: the mode number);
//   - parameters: PX4 puts integers into PARAM_VALUE byte-wise, ArduPilot casts them to float;
//   - missions: ArduPilot's list starts with home (item 0, overwritten on upload; MISSION_CURRENT
//     and MISSION_ITEM_REACHED count it), PX4's with the first item;
//   - commands: PX4 takes NAV_TAKEOFF at an AMSL altitude from any mode, DO_REPOSITION, and
//     MISSION_START; ArduCopter takes off only in Guided (FAILED otherwise, as Copter answers),
//     refuses to arm in Auto, and flies the mission in Auto after MISSION_START;
//   - telemetry: SYS_STATUS (with the pre-arm bit), GLOBAL_POSITION_INT, ATTITUDE, GPS_RAW_INT,
//     VFR_HUD, EXTENDED_SYS_STATE, HOME_POSITION, MISSION_CURRENT, BATTERY_STATUS, STATUSTEXT;
//   - a camera (component 100) that acknowledges CAMERA_TRACK_RECTANGLE, and RTP/H.264 video
//     from GStreamer's test source (--video PORT).
// Kinematics are a point flying at the mission's speed, sped up by --rate for short tests.
// Faults on request: --silent (telemetry only; no service answers), --stop-upload-at N (stops
// asking for mission items at item N), --unknown (sends messages our GCS does not read),
// --drop-every N (every Nth frame lost, as on a lossy radio),
// --passphrase (signs with that key's SHA-256, and takes only frames signed with it).
'use strict';
const dgram = require('dgram');
const { spawn } = require('child_process');
const { PassThrough } = require('stream');
const {
  MavLinkPacketSplitter, MavLinkPacketParser, MavLinkProtocolV2, MavLinkPacketSignature, minimal, standard, common,
} = require('node-mavlink');

const args = { autopilot: 'px4', sysid: '1', gcs: '127.0.0.1:14550', rate: '4' };
for (let i = 2; i < process.argv.length; i++) {
  const name = process.argv[i].replace(/^--/, '');
  if (['silent', 'unknown'].includes(name)) args[name] = true;
  else args[name] = process.argv[++i];
}
const PX4 = args.autopilot === 'px4';
const COPTER = args.autopilot === 'arducopter';
if (!PX4 && !COPTER) throw new Error(`--autopilot px4 or arducopter, not ${args.autopilot}`);
const SYSID = Number(args.sysid), COMPID = 1, CAMERA = 100;
const RATE = Number(args.rate);  // simulated seconds per second
const key = args.passphrase ? MavLinkPacketSignature.key(args.passphrase) : null;
const REGISTRY = { ...minimal.REGISTRY, ...standard.REGISTRY, ...common.REGISTRY };
const HOME = { lat: 1.2966, lon: 103.7764, alt: 15.0 };
const M_PER_DEG = 111319.49;

// ---- modes ----
const px4 = (main, sub = 0) => ((main << 16) | (sub << 24)) >>> 0;
const MODES = PX4
  ? { hold: px4(4, 3), takeoff: px4(4, 2), mission: px4(4, 4), rtl: px4(4, 5), land: px4(4, 6), position: px4(3) }
  : { stabilize: 0, auto: 3, guided: 4, loiter: 5, rtl: 6, land: 9, brake: 17 };
let mode = PX4 ? MODES.hold : MODES.loiter;

// ---- parameters: [id, type, value] (MAV_PARAM_TYPE 2 INT8, 4 INT16, 6 INT32, 9 REAL32) ----
const params = PX4
  ? [['MPC_XY_CRUISE', 9, 6.0], ['MIS_TAKEOFF_ALT', 9, 2.5], ['RTL_RETURN_ALT', 9, 30.0], ['COM_DISARM_LAND', 9, 2.0],
     ['NAV_DLL_ACT', 6, 2], ['COM_RCL_EXCEPT', 6, 4], ['SYS_AUTOSTART', 6, 4001], ['MAV_SYS_ID', 6, SYSID],
     ['CAL_ACC0_ID', 6, 1310988], ['GF_ACTION', 6, 1]]
  : [['WPNAV_SPEED', 9, 600.0], ['RTL_ALT', 6, 1500], ['FENCE_ENABLE', 2, 0], ['ARMING_CHECK', 6, 1],
     ['SYSID_THISMAV', 4, SYSID], ['LAND_SPEED', 4, 50], ['WP_YAW_BEHAVIOR', 2, 2], ['FRAME_CLASS', 2, 1],
     ['PILOT_SPEED_UP', 4, 250], ['WPNAV_SPEED_DN', 9, 150.0]];
const LIMITS = { MPC_XY_CRUISE: [3, 20], WPNAV_SPEED: [20, 2000] };
function encodeParam(type, value) {
  if (type === 9 || !PX4) return value;  // ArduPilot: C-cast; reals are floats on both
  const b = Buffer.alloc(4);
  if (type === 2) b.writeInt8(value, 0); else if (type === 4) b.writeInt16LE(value, 0); else b.writeInt32LE(value, 0);
  return b.readFloatLE(0);
}
function decodeParam(type, wire) {
  if (type === 9 || !PX4) return wire;
  const b = Buffer.alloc(4);
  b.writeFloatLE(wire, 0);
  return type === 2 ? b.readInt8(0) : type === 4 ? b.readInt16LE(0) : b.readInt32LE(0);
}
const param = (id) => params.find((p) => p[0] === id);
const cruise = () => (PX4 ? param('MPC_XY_CRUISE')[2] : param('WPNAV_SPEED')[2] / 100);

// ---- the link ----
const socket = dgram.createSocket('udp4');
const [gcsHost, gcsPort] = args.gcs.split(':');
const input = new PassThrough();
socket.on('message', (msg) => input.write(msg));
const seqs = {};  // the sequence is per component (the camera counts its own)
let lastTs = 0, sentFrames = 0;
function send(message, compid = COMPID) {
  // --drop-every N: every Nth frame is numbered but never sent (a lossy radio).
  const seq = seqs[compid] = ((seqs[compid] === undefined ? -1 : seqs[compid]) + 1) & 255;
  if (args['drop-every'] && ++sentFrames % Number(args['drop-every']) === 0) return;
  const protocol = new MavLinkProtocolV2(SYSID, compid, key ? MavLinkProtocolV2.IFLAG_SIGNED : 0);
  let buffer = protocol.serialize(message, seq);
  if (key) {
    lastTs = Math.max(Date.now(), lastTs + 1);
    buffer = protocol.sign(buffer, 0, key, lastTs);
  }
  socket.send(buffer, Number(gcsPort), gcsHost);
}
let textId = 0;
function text(severity, t) {
  // Longer than 50 characters: chunks of 50 sharing an id, the last one shorter (MAVLink 2).
  const id = t.length > 50 ? ++textId : 0;
  for (let i = 0, chunk = 0; i === 0 || i < t.length + (t.length % 50 === 0 ? 1 : 0); i += 50, chunk++) {
    const s = new common.StatusText();
    s.severity = severity; s.text = t.slice(i, i + 50); s.id = id; s.chunkSeq = chunk;
    send(s);
    if (!id) break;
  }
  console.log(`  ${args.autopilot} says: ${t}`);
}
function ack(command, result, compid = COMPID) {
  const a = new common.CommandAck();
  a.command = command; a.result = result; a.progress = 0; a.resultParam2 = 0; a.targetSystem = 255; a.targetComponent = 190;
  send(a, compid);
}

// ---- the vehicle ----
const v = { north: 0, east: 0, up: 0, vn: 0, ve: 0, vu: 0, yaw: 0, armed: false, landed: true };
let activity = { kind: 'idle' };
const lists = { 0: [], 1: [], 2: [] };  // mission, fence, rally as the vehicle holds them
if (!PX4) lists[0] = [homeItem()];
let current = PX4 ? 0 : 1;               // MISSION_CURRENT
let upload = null;
let lastReached = -1;
function homeItem() {
  return { frame: 0, command: 16, param1: 0, param2: 0, param3: 0, param4: 0,
           x: Math.round(HOME.lat * 1e7), y: Math.round(HOME.lon * 1e7), z: HOME.alt, autocontinue: 1 };
}
function neOf(lat, lon) { return [(lat - HOME.lat) * M_PER_DEG, (lon - HOME.lon) * M_PER_DEG * Math.cos(HOME.lat * Math.PI / 180)]; }
function altAboveHome(frame, z) { return frame === 0 || frame === 5 ? z - HOME.alt : z; }

function setMode(m, why) {
  if (mode === m) return;
  mode = m;
  if (why) console.log(`  mode ${m} (${why})`);
}
function startMission() {
  const items = lists[0];
  const first = PX4 ? 0 : 1;
  if (items.length <= first) return false;
  current = first;
  activity = { kind: 'mission' };
  text(6, `Mission started: ${items.length - first} items, from item ${first} (home is item 0 on ArduPilot, not on PX4)`);
  setMode(PX4 ? MODES.mission : MODES.auto, 'mission');
  beginItem();
  return true;
}
function beginItem() {
  const it = lists[0][current];
  if (!it) return;
  const c = it.command;
  if (c === 22) activity.leg = { kind: 'climb', alt: altAboveHome(it.frame, it.z) };
  else if (c === 16) {
    const [n, e] = neOf(it.x / 1e7, it.y / 1e7);
    activity.leg = { kind: 'fly', n, e, alt: altAboveHome(it.frame, it.z) };
  } else if (c === 21) {
    const [n, e] = it.x ? neOf(it.x / 1e7, it.y / 1e7) : [v.north, v.east];
    activity.leg = { kind: 'land', n, e };
  } else if (c === 20) activity.leg = { kind: 'rtl', phase: 'climb' };
  else activity.leg = { kind: 'instant' };
}
function reached(index) {
  if (index === lastReached) return;
  lastReached = index;
  const r = new common.MissionItemReached();
  r.seq = index;
  send(r);
}
function nextItem() {
  reached(current);
  if (current + 1 >= lists[0].length) { activity = { kind: 'hold' }; setMode(PX4 ? MODES.hold : MODES.loiter, 'mission done'); return; }
  current++;
  beginItem();
}

// Moves toward (n, e, alt) at the cruise speed; true when there.
function flyTo(n, e, alt, dt) {
  const dn = n - v.north, de = e - v.east, du = alt - v.up;
  const d = Math.hypot(dn, de);
  const step = cruise() * dt;
  if (d > 1e-6) { const k = Math.min(1, step / d); v.vn = dn * k / dt; v.ve = de * k / dt; v.north += dn * k; v.east += de * k; v.yaw = Math.atan2(de, dn); } else { v.vn = v.ve = 0; }
  const climb = 3 * dt;
  const kz = Math.abs(du) <= climb ? du : Math.sign(du) * climb;
  v.up += kz; v.vu = kz / dt;
  return Math.hypot(n - v.north, e - v.east) < 0.3 && Math.abs(alt - v.up) < 0.2;
}
function descend(dt) {
  v.vn = v.ve = 0;
  v.up = Math.max(0, v.up - 2 * dt);
  v.vu = -2;
  if (v.up > 0) return false;
  v.vu = 0;
  v.landed = true;
  v.armed = false;  // both autopilots disarm after touching down
  text(6, PX4 ? 'Landing detected' : 'Land complete');
  text(6, PX4 ? 'Disarmed by landing' : 'Disarming motors');
  return true;
}
function step(dt) {
  if (!v.armed) { v.vn = v.ve = v.vu = 0; return; }
  const a = activity;
  if (a.kind === 'takeoff') { if (flyTo(v.north, v.east, a.alt, dt)) { activity = { kind: 'hold' }; if (PX4) setMode(MODES.hold, 'takeoff done'); } }
  else if (a.kind === 'goto') { flyTo(a.n, a.e, a.alt, dt); }
  else if (a.kind === 'land') { if (descend(dt)) activity = { kind: 'idle' }; }
  else if (a.kind === 'rtl') {
    if (a.phase === 'climb' && flyTo(v.north, v.east, Math.max(a.alt, v.up), dt)) a.phase = 'home';
    else if (a.phase === 'home' && flyTo(0, 0, v.up, dt)) a.phase = 'land';
    else if (a.phase === 'land' && descend(dt)) activity = { kind: 'idle' };
  } else if (a.kind === 'mission' && a.leg) {
    const l = a.leg;
    if (l.kind === 'instant') nextItem();
    else if (l.kind === 'climb') { v.landed = false; if (flyTo(v.north, v.east, l.alt, dt)) nextItem(); }
    else if (l.kind === 'fly') { if (flyTo(l.n, l.e, l.alt, dt)) nextItem(); }
    else if (l.kind === 'land') { if (l.down || flyTo(l.n, l.e, v.up, dt)) { l.down = true; if (descend(dt)) { reached(current); activity = { kind: 'idle' }; } } }
    else if (l.kind === 'rtl') {
      if (l.phase === 'climb' && flyTo(v.north, v.east, Math.max(15, v.up), dt)) l.phase = 'home';
      else if (l.phase === 'home' && flyTo(0, 0, v.up, dt)) l.phase = 'land';
      else if (l.phase === 'land' && descend(dt)) { reached(current); activity = { kind: 'idle' }; }
    }
  }
  if (v.up > 0.05) v.landed = false;
}

// ---- commands ----
const RESULT = { ACCEPTED: 0, TEMPORARILY_REJECTED: 1, DENIED: 2, UNSUPPORTED: 3, FAILED: 4 };
function onCommand(c, isInt) {
  if (c.targetSystem !== SYSID) return;
  // node-mavlink names COMMAND_INT's x, y, z _param5.._param7 as well (x, y in 1e-7 degrees).
  const p = [c._param1, c._param2, c._param3, c._param4, c._param5, c._param6, c._param7];
  const cmd = c.command;
  if (c.targetComponent === CAMERA) {
    if (cmd === 2005 || cmd === 2010) return ack(cmd, RESULT.ACCEPTED, CAMERA);
    return ack(cmd, RESULT.UNSUPPORTED, CAMERA);
  }
  switch (cmd) {
    case 400: {  // COMPONENT_ARM_DISARM
      if (p[0] === 1) {
        if (!PX4 && mode === MODES.auto) { text(3, 'Arm: Mode not armable'); return ack(cmd, RESULT.FAILED); }
        v.armed = true; text(6, PX4 ? 'Armed by external command' : 'Arming motors');
      } else {
        if (!v.landed && p[1] !== 21196) { text(4, 'Disarm: not landed'); return ack(cmd, RESULT.DENIED); }
        v.armed = false; activity = { kind: 'idle' };
      }
      return ack(cmd, RESULT.ACCEPTED);
    }
    case 22: {  // NAV_TAKEOFF
      if (!v.armed) { text(4, 'Takeoff denied: disarmed'); return ack(cmd, PX4 ? RESULT.DENIED : RESULT.FAILED); }
      if (!PX4 && mode !== MODES.guided) return ack(cmd, RESULT.FAILED);  // Copter: Guided only
      const alt = PX4 ? p[6] - HOME.alt : p[6];
      activity = { kind: 'takeoff', alt };
      if (PX4) setMode(MODES.takeoff, 'takeoff');
      v.landed = false;
      return ack(cmd, RESULT.ACCEPTED);
    }
    case 21: activity = { kind: 'land' }; if (PX4) setMode(MODES.land, 'land'); return ack(cmd, RESULT.ACCEPTED);
    case 20: activity = { kind: 'rtl', phase: 'climb', alt: 15 }; setMode(PX4 ? MODES.rtl : MODES.rtl, 'rtl'); return ack(cmd, RESULT.ACCEPTED);
    case 192: {  // DO_REPOSITION
      if (!v.armed) return ack(cmd, RESULT.DENIED);
      if (!PX4 && mode !== MODES.guided) return ack(cmd, RESULT.FAILED);
      const [n, e] = neOf(p[4] / 1e7, p[5] / 1e7);
      const alt = isInt && (c.frame === 3 || c.frame === 6) ? p[6] : p[6] - HOME.alt;
      activity = { kind: 'goto', n, e, alt };
      if (PX4) setMode(MODES.hold, 'reposition');
      return ack(cmd, RESULT.ACCEPTED);
    }
    case 300: {  // MISSION_START
      if (!v.armed) { text(4, 'Mission start denied: disarmed'); return ack(cmd, PX4 ? RESULT.DENIED : RESULT.FAILED); }
      if (!PX4 && mode !== MODES.auto) return ack(cmd, RESULT.FAILED);
      if (!startMission()) { text(4, 'No mission to start'); return ack(cmd, RESULT.DENIED); }
      return ack(cmd, RESULT.ACCEPTED);
    }
    case 176: {  // DO_SET_MODE
      const want = PX4 ? px4(p[1], p[2]) : p[1];
      if (!Object.values(MODES).includes(want >>> 0)) return ack(cmd, RESULT.UNSUPPORTED);
      if (PX4 && want === MODES.mission) { if (!v.armed || !startMission()) return ack(cmd, RESULT.DENIED); return ack(cmd, RESULT.ACCEPTED); }
      setMode(want >>> 0, 'DO_SET_MODE');
      if (want === (PX4 ? MODES.hold : MODES.loiter) || want === MODES.brake) activity = { kind: 'hold' };
      if (want === MODES.land) activity = { kind: 'land' };
      if (want === MODES.rtl) activity = { kind: 'rtl', phase: 'climb', alt: 15 };
      if (!PX4 && want === MODES.guided) activity = { kind: 'hold' };
      return ack(cmd, RESULT.ACCEPTED);
    }
    case 511:  // SET_MESSAGE_INTERVAL: ArduPilot streams what a GCS asks for
      streams.add(p[0]);
      return ack(cmd, RESULT.ACCEPTED);
    case 512: {  // REQUEST_MESSAGE
      if (p[0] === 148) sendVersion(); else if (p[0] === 242) sendHome(); else return ack(cmd, RESULT.UNSUPPORTED);
      return ack(cmd, RESULT.ACCEPTED);
    }
    default: return ack(cmd, RESULT.UNSUPPORTED);
  }
}

// ---- parameters ----
function sendParam(i) {
  const [id, type, value] = params[i];
  const m = new common.ParamValue();
  m.paramId = id; m.paramValue = encodeParam(type, value); m.paramType = type; m.paramCount = params.length; m.paramIndex = i;
  send(m);
}
function onParamSet(m) {
  const i = params.findIndex((q) => q[0] === m.paramId);
  if (i < 0) return;
  const value = decodeParam(params[i][1], m.paramValue);
  const limits = LIMITS[m.paramId];
  if (limits && (value < limits[0] || value > limits[1])) text(4, `${m.paramId}: ${value} out of range`);
  else params[i][2] = value;
  sendParam(i);
}

// ---- missions ----
function missionAck(type, result) {
  const a = new common.MissionAck();
  a.targetSystem = 255; a.targetComponent = 190; a.type = result; a.missionType = type;
  send(a);
}
function requestItem() {
  upload.last = Date.now();
  if (args['stop-upload-at'] !== undefined && upload.type === 0 && upload.items.length >= Number(args['stop-upload-at'])) return;
  const r = new common.MissionRequestInt();
  r.targetSystem = 255; r.targetComponent = 190; r.seq = upload.items.length; r.missionType = upload.type;
  send(r);
}
function onMissionCount(m) {
  upload = { type: m.missionType, count: m.count, items: [] };
  if (m.count === 0) { lists[m.missionType] = PX4 || m.missionType ? [] : [homeItem()]; upload = null; return missionAck(m.missionType, 0); }
  requestItem();
}
function onMissionItem(m) {
  if (!upload || m.missionType !== upload.type || m.seq !== upload.items.length) return;
  upload.items.push({ frame: m.frame, command: m.command, param1: m.param1, param2: m.param2, param3: m.param3, param4: m.param4,
                      x: m.x, y: m.y, z: m.z, autocontinue: m.autocontinue });
  if (upload.items.length < upload.count) return requestItem();
  const items = upload.items;
  if (!PX4 && upload.type === 0) items[0] = homeItem();  // ArduPilot keeps its own home as item 0
  lists[upload.type] = items;
  const type = upload.type;
  upload = null;
  missionAck(type, 0);
  if (type === 0) { current = PX4 ? 0 : 1; lastReached = -1; }
}
function sendItem(type, s) {
  const it = lists[type][s];
  if (!it) return missionAck(type, 13);  // INVALID_SEQUENCE
  const m = new common.MissionItemInt();
  Object.assign(m, { targetSystem: 255, targetComponent: 190, seq: s, frame: it.frame, command: it.command, current: s === 0 ? 1 : 0,
                     autocontinue: it.autocontinue, param1: it.param1, param2: it.param2, param3: it.param3, param4: it.param4,
                     x: it.x, y: it.y, z: it.z, missionType: type });
  send(m);
}

// ---- telemetry ----
function sendVersion() {
  const a = new standard.AutopilotVersion();
  // MISSION_INT 4, COMMAND_INT 8, MISSION_FENCE 1024, MISSION_RALLY 2048, MAVLINK2 8192, and the
  // parameter encoding: PARAM_ENCODE_BYTEWISE 16 (PX4) or PARAM_ENCODE_C_CAST 131072 (ArduPilot).
  a.capabilities = BigInt(4 | 8 | 1024 | 2048 | 8192 | (PX4 ? 16 : 131072));
  a.flightSwVersion = PX4 ? 0x010f0000 : 0x04050000;
  send(a);
}
function sendHome() {
  const h = new common.HomePosition();
  h.latitude = Math.round(HOME.lat * 1e7); h.longitude = Math.round(HOME.lon * 1e7); h.altitude = Math.round(HOME.alt * 1000);
  h.x = h.y = h.z = 0; h.q = [1, 0, 0, 0]; h.approachX = h.approachY = h.approachZ = 0;
  send(h);
}
let tick = 0;
// ArduPilot sends a GCS only the streams it asked for (SET_MESSAGE_INTERVAL; SRn_ parameters at
// zero); PX4 streams its set to a GCS link unasked.
const streams = new Set();
const streamed = (id) => PX4 || streams.has(id);
function telemetry() {
  tick++;
  const lat = HOME.lat + v.north / M_PER_DEG, lon = HOME.lon + v.east / (M_PER_DEG * Math.cos(HOME.lat * Math.PI / 180));
  const g = new common.GlobalPositionInt();
  Object.assign(g, { timeBootMs: Math.round(process.uptime() * 1000), lat: Math.round(lat * 1e7), lon: Math.round(lon * 1e7),
                     alt: Math.round((HOME.alt + v.up) * 1000), relativeAlt: Math.round(v.up * 1000),
                     vx: Math.round(v.vn * 100), vy: Math.round(v.ve * 100), vz: Math.round(-v.vu * 100), hdg: 0 });
  if (streamed(33)) send(g);
  const a = new common.Attitude();
  Object.assign(a, { timeBootMs: g.timeBootMs, roll: 0, pitch: 0, yaw: v.yaw, rollspeed: 0, pitchspeed: 0, yawspeed: 0 });
  if (streamed(30)) send(a);
  if (tick % 5 === 0) {
    const gps = new common.GpsRawInt();
    Object.assign(gps, { timeUsec: BigInt(Date.now()) * 1000n, fixType: 3, lat: g.lat, lon: g.lon, alt: g.alt, eph: 80, epv: 120,
                         vel: 0, cog: 0, satellitesVisible: 14 });
    if (streamed(24)) send(gps);
    const h = new common.VfrHud();
    Object.assign(h, { airspeed: 0, groundspeed: Math.hypot(v.vn, v.ve), heading: 0, throttle: 50, alt: HOME.alt + v.up, climb: v.vu });
    if (streamed(74)) send(h);
  }
  if (tick % 10 === 0) {
    const hb = new minimal.Heartbeat();
    // MAV_MODE_FLAG: custom mode enabled 1, stabilize 16, guided 8, auto 4, armed 128.
    Object.assign(hb, { type: 2, autopilot: PX4 ? 12 : 3, baseMode: 1 | 16 | 8 | 4 | (v.armed ? 128 : 0), customMode: mode,
                        systemStatus: v.armed ? 4 : 3, mavlinkVersion: 3 });
    send(hb);
    const s = new common.SysStatus();
    const sensors = 1 | 2 | 4 | 8 | 32 | (1 << 21) | (1 << 25) | (1 << 28);
    Object.assign(s, { onboardControlSensorsPresent: sensors, onboardControlSensorsEnabled: sensors, onboardControlSensorsHealth: sensors,
                       load: 300, voltageBattery: 16200, currentBattery: 500, batteryRemaining: 87, dropRateComm: 0, errorsComm: 0,
                       errorsCount1: 0, errorsCount2: 0, errorsCount3: 0, errorsCount4: 0 });
    if (streamed(1)) send(s);
    const e = new common.ExtendedSysState();
    e.vtolState = 0; e.landedState = v.landed ? 1 : activity.kind === 'land' ? 4 : 2;
    if (streamed(245)) send(e);
    const c = new common.MissionCurrent();
    c.seq = current;
    if (streamed(42)) send(c);
    if (args.unknown) {  // messages our GCS does not read (VIBRATION, ESTIMATOR_STATUS)
      const vib = new common.Vibration();
      Object.assign(vib, { timeUsec: BigInt(Date.now()) * 1000n, vibrationX: 0.1, vibrationY: 0.1, vibrationZ: 0.2, clipping0: 0, clipping1: 0, clipping2: 0 });
      send(vib);
    }
  }
  if (PX4 && tick % 50 === 0) sendHome();  // PX4 streams it; ArduPilot sends it when asked
}

// ---- dispatch ----
const accepted = { frames: 0, refused: 0 };
input.pipe(new MavLinkPacketSplitter()).pipe(new MavLinkPacketParser()).on('data', (packet) => {
  if (key && (!packet.signature || !packet.signature.matches(key))) { accepted.refused++; return; }
  accepted.frames++;
  const clazz = REGISTRY[packet.header.msgid];
  if (!clazz || args.silent) return;
  const m = packet.protocol.data(packet.payload, clazz);
  switch (clazz.MSG_NAME) {
    case 'COMMAND_LONG': return onCommand(m, false);
    case 'COMMAND_INT': return onCommand(m, true);
    case 'PARAM_REQUEST_LIST': if (m.targetSystem === SYSID) params.forEach((_, i) => sendParam(i)); return;
    case 'PARAM_REQUEST_READ': if (m.targetSystem === SYSID) { const i = m.paramIndex >= 0 ? m.paramIndex : params.findIndex((p) => p[0] === m.paramId); if (params[i]) sendParam(i); } return;
    case 'PARAM_SET': if (m.targetSystem === SYSID) onParamSet(m); return;
    case 'MISSION_COUNT': if (m.targetSystem === SYSID) onMissionCount(m); return;
    case 'MISSION_ITEM_INT': if (m.targetSystem === SYSID) onMissionItem(m); return;
    case 'MISSION_REQUEST_LIST': if (m.targetSystem === SYSID) { const c = new common.MissionCount(); Object.assign(c, { targetSystem: 255, targetComponent: 190, count: lists[m.missionType].length, missionType: m.missionType }); send(c); } return;
    case 'MISSION_REQUEST_INT': if (m.targetSystem === SYSID) sendItem(m.missionType, m.seq); return;
    default: return;
  }
});

socket.bind(0, '127.0.0.1', () => {
  console.log(`mock ${args.autopilot} (system ${SYSID}) -> ${args.gcs}${key ? ', signed' : ''}${args.silent ? ', silent' : ''}` +
              `${args['stop-upload-at'] !== undefined ? `, stops the upload at item ${args['stop-upload-at']}` : ''}`);
  let last = Date.now();
  setInterval(() => {
    const now = Date.now();
    const dt = (now - last) / 1000 * RATE;
    last = now;
    step(dt);
    telemetry();
    if (upload && Date.now() - upload.last > 1500 && args['stop-upload-at'] === undefined) requestItem();
  }, 100);
});
if (args.video) {  // RTP/H.264 as a PX4 camera streams it to QGroundControl
  const gst = spawn('gst-launch-1.0', ['-q', 'videotestsrc', 'pattern=ball', 'is-live=true', '!', 'video/x-raw,width=320,height=240,framerate=15/1',
    '!', 'x264enc', 'tune=zerolatency', 'speed-preset=ultrafast', 'key-int-max=15', '!', 'rtph264pay', 'config-interval=1', 'pt=96',
    '!', 'udpsink', 'host=127.0.0.1', `port=${args.video}`], { stdio: 'inherit' });
  const stop = () => { gst.kill(); process.exit(0); };
  process.on('SIGTERM', stop);
  process.on('SIGINT', stop);
}
process.on('SIGTERM', () => { console.log(`mock ${args.autopilot}: ${accepted.frames} frames taken, ${accepted.refused} refused`); process.exit(0); });
