// A scripted QGroundControl-style ground station written with npm's node-mavlink, an
// implementation of MAVLink independent of ours. It listens on UDP 14550 as QGroundControl does,
// follows QGroundControl's connect sequence (heartbeat, AUTOPILOT_VERSION, the full parameter
// list, mission, fence and rally download), uploads a survey mission (planned by uav-survey as a
// QGroundControl .plan around the vehicle's home) with a fence and rally points, tries the bad
// inputs a vehicle must refuse, arms, starts the mission, sees every item reached and the
// landing, changes a parameter, and checks that every frame it received was signed with the
// key of the shared passphrase. Prints one line per step; exits 0 only when every check held.
//
// Usage: node qgc_client.js --bin DIR --passphrase TEXT [--port 14550] [--report FILE] [--timeout S]
//          [--lcm-param NAME=VALUE]  after the landing, expect this change by our GCS on LCM
'use strict';
const fs = require('fs');
const os = require('os');
const path = require('path');
const { execFileSync } = require('child_process');
const {
  args, key, wrongKey, report, listeners, frame, sendRaw, send, sent, waitFor, collect, sleep, check, commandLong,
  command, commandStarted, listen, startHeartbeat, minimal, common,
} = require('./gcs_link');

const port = Number(args.port || 14550);
const flightTimeoutS = Number(args.timeout || 900);
const target = 1;  // the vehicle's system id

// ---- the mission protocol, GCS side ----
async function download(type) {
  const req = new common.MissionRequestList();
  req.targetSystem = target; req.targetComponent = 1; req.missionType = type;
  const countP = waitFor('MISSION_COUNT', (d) => d.missionType === type, 3000, `MISSION_COUNT of type ${type}`);
  send(req);
  const { count } = await countP;
  const items = [];
  for (let s = 0; s < count; s++) {
    const r = new common.MissionRequestInt();
    r.targetSystem = target; r.targetComponent = 1; r.seq = s; r.missionType = type;
    const itemP = waitFor('MISSION_ITEM_INT', (d) => d.seq === s && d.missionType === type, 3000, `item ${s}`);
    send(r);
    items.push(await itemP);
  }
  const ack = new common.MissionAck();
  ack.targetSystem = target; ack.targetComponent = 1; ack.type = 0; ack.missionType = type;
  send(ack);
  return items;
}

// Uploads `items` ({command, frame, params[7]}) as mission type `type`; resolves with the
// MISSION_ACK result. `stopAfter`: stop answering after that many items (a GCS that goes away).
async function upload(type, items, { stopAfter, timeoutMs = 15000 } = {}) {
  return new Promise((resolve, reject) => {
    const timer = setTimeout(() => { listeners.delete(l); reject(new Error(`upload of type ${type} timed out`)); }, timeoutMs);
    const requested = [];
    const l = (n, d) => {
      if ((n === 'MISSION_REQUEST_INT' || n === 'MISSION_REQUEST') && d.missionType === type) {
        requested.push(d.seq);
        if (stopAfter !== undefined && d.seq >= stopAfter) return;
        const it = items[d.seq];
        const m = new common.MissionItemInt();
        m.targetSystem = target; m.targetComponent = 1; m.seq = d.seq;
        m.frame = it.frame; m.command = it.command; m.current = 0; m.autocontinue = 1;
        const p = it.params.map((v) => (v === null ? NaN : v));
        m.param1 = p[0]; m.param2 = p[1]; m.param3 = p[2]; m.param4 = p[3];
        const position = it.frame !== 2;
        m.x = position ? Math.round(p[4] * 1e7) : Math.round(p[4] || 0);
        m.y = position ? Math.round(p[5] * 1e7) : Math.round(p[5] || 0);
        m.z = p[6];
        m.missionType = type;
        send(m);
      } else if (n === 'MISSION_ACK' && d.missionType === type) {
        clearTimeout(timer);
        listeners.delete(l);
        resolve({ result: d.type, requested });
      }
    };
    listeners.add(l);
    const c = new common.MissionCount();
    c.targetSystem = target; c.targetComponent = 1; c.count = items.length; c.missionType = type;
    send(c);
  });
}

// The .plan's mission items, flattened as QGroundControl sends them (a survey's own items).
function planItems(plan) {
  const out = [];
  for (const it of plan.mission.items) {
    if (it.type === 'SimpleItem') out.push({ command: it.command, frame: it.frame, params: it.params });
    else for (const s of it.TransectStyleComplexItem.Items) out.push({ command: s.command, frame: s.frame, params: s.params });
  }
  return out;
}

function offset(home, north, east) {  // flat-earth offset, metres to degrees
  const R = 6378137;
  return [home.lat + (north / R) * 180 / Math.PI,
          home.lon + (east / (R * Math.cos(home.lat * Math.PI / 180))) * 180 / Math.PI];
}

async function main() {
  await listen(port);
  console.log(`qgc_client: listening on UDP ${port} as QGroundControl does`);

  // 1. The vehicle's heartbeat.
  const hb = await waitFor('HEARTBEAT', (d, p) => p.header.compid === 1, 30000, 'the vehicle\'s HEARTBEAT');
  check(hb.autopilot === 12, `heartbeat: autopilot ${hb.autopilot} (12: PX4), type ${hb.type}, custom mode 0x${hb.customMode.toString(16)}`);
  startHeartbeat();

  // 2. AUTOPILOT_VERSION.
  const versionP = waitFor('AUTOPILOT_VERSION', null, 5000);
  const versionAck = await command(512, [148]);
  const version = await versionP;
  const caps = Number(version.capabilities);
  check(versionAck.result === 0 && (caps & 4) && (caps & 8) && (caps & 8192),
        `AUTOPILOT_VERSION: capabilities 0x${caps.toString(16)} (MISSION_INT, COMMAND_INT, MAVLINK2)`);

  // 3. The full parameter list, missing ones read by index (QGroundControl's way).
  const params = new Map();
  let paramCount = -1;
  const onParam = (n, d) => { if (n === 'PARAM_VALUE') { paramCount = d.paramCount; params.set(d.paramIndex, d); } };
  listeners.add(onParam);
  const list = new common.ParamRequestList();
  list.targetSystem = target; list.targetComponent = 1;
  send(list);
  const t0 = Date.now();
  while ((paramCount < 0 || params.size < paramCount) && Date.now() - t0 < 20000) {
    await sleep(500);
    if (paramCount > 0 && Date.now() - t0 > 3000)
      for (let i = 0; i < paramCount; i++) if (!params.has(i)) {
        const r = new common.ParamRequestRead();
        r.targetSystem = target; r.targetComponent = 1; r.paramId = ''; r.paramIndex = i;
        send(r);
      }
  }
  listeners.delete(onParam);
  const ids = [...params.values()].map((p) => p.paramId);
  check(paramCount > 0 && params.size === paramCount && new Set(ids).size === ids.length && ids.every((id) => id.length <= 16),
        `parameters: ${params.size} of ${paramCount}, ids unique and at most 16 characters, in ${Date.now() - t0} ms`);
  report.parameters = params.size;

  // 4. Mission, fence and rally download (empty on a fresh vehicle).
  const before = [await download(0), await download(1), await download(2)];
  check(before.every((l) => Array.isArray(l)), `download: mission ${before[0].length}, fence ${before[1].length}, rally ${before[2].length} items`);

  // 5. Home, and the survey planned around it (uav-demo's: 40 x 60 m at 25 m, 5-45 m north).
  const homeP = waitFor('HOME_POSITION', null, 5000);
  await command(512, [242]);
  const h = await homeP;
  const home = { lat: h.latitude * 1e-7, lon: h.longitude * 1e-7, alt: h.altitude * 1e-3 };
  const corners = [[5, -30], [5, 30], [45, 30], [45, -30]].map(([n, e]) => offset(home, n, e));
  const planFile = path.join(os.tmpdir(), `qgc_client_${process.pid}.plan`);
  execFileSync(path.join(args.bin, 'uav-survey'), ['--polygon', corners.map((c) => c.join(',')).join(' '),
    '--home', `${home.lat},${home.lon},${home.alt}`, '--altitude', '25', '--plan', planFile]);
  const plan = JSON.parse(fs.readFileSync(planFile, 'utf8'));
  fs.unlinkSync(planFile);
  const items = planItems(plan);
  console.log(`planned: ${items.length} mission items from uav-survey's .plan around home ${home.lat.toFixed(6)}, ${home.lon.toFixed(6)}`);

  // 6. Bad input first: nothing of it may change the vehicle.
  const bad = items.map((it) => ({ ...it }));
  bad.splice(2, 0, { command: 31000, frame: 2, params: [0, 0, 0, 0, 0, 0, 0] });  // MAV_CMD_USER_1: not flyable
  const badUp = await upload(0, bad);
  check(badUp.result === 3, `a mission with a command the vehicle cannot fly: MISSION_ACK ${badUp.result} (3: UNSUPPORTED)`);
  const far = items.map((it) => ({ ...it, params: [...it.params] }));
  far[3].params[6] = 500;  // 500 m above home: over the vehicle's ceiling
  const farUp = await upload(0, far);
  check(farUp.result === 5, `a waypoint 500 m up: MISSION_ACK ${farUp.result} (5: INVALID, the vehicle's ceiling)`);
  const stopped = await upload(0, items, { stopAfter: 3, timeoutMs: 20000 });
  check(stopped.result === 15 && stopped.requested.length > 4,
        `an upload that stops at item 3: re-requested ${stopped.requested.length - 4} times, then MISSION_ACK ${stopped.result} (15: CANCELLED)`);
  check((await download(0)).length === 0, 'the vehicle still holds no mission after the three refused uploads');

  // 7. The survey, a fence around home and two rally points.
  const up = await upload(0, items);
  check(up.result === 0, `mission upload: MISSION_ACK ${up.result} (0: ACCEPTED), ${up.requested.length} items requested`);
  const fence = [{ command: 5003, frame: 3, params: [300, 0, 0, 0, home.lat, home.lon, 0] }];
  const rally = [[20, 0], [0, 20]].map(([n, e]) => { const [la, lo] = offset(home, n, e); return { command: 5100, frame: 3, params: [0, 0, 0, 0, la, lo, 15] }; });
  check((await upload(1, fence)).result === 0, 'fence upload (a 300 m keep-in circle): accepted');
  check((await upload(2, rally)).result === 0, 'rally upload (two points): accepted');
  const after = [await download(0), await download(1), await download(2)];
  const same = after[0].length === items.length && after[0].every((m, i) => m.command === items[i].command &&
    (items[i].frame === 2 || Math.abs(m.x - Math.round(items[i].params[4] * 1e7)) <= 1));
  check(same && after[1].length === 1 && after[2].length === 2,
        `download after upload: mission ${after[0].length} items (same commands and positions), fence ${after[1].length}, rally ${after[2].length}`);

  // 8. Parameters: out of range refused with the value unchanged; in range applied.
  const speedId = 'ctl_speed_max_xy';
  const old = [...params.values()].find((p) => p.paramId === speedId);
  const setParam = async (value) => {
    const s = new common.ParamSet();
    s.targetSystem = target; s.targetComponent = 1; s.paramId = speedId; s.paramValue = value; s.paramType = 9;
    const answer = waitFor('PARAM_VALUE', (d) => d.paramId === speedId, 5000, `PARAM_VALUE of ${speedId}`);
    send(s);
    return (await answer).paramValue;
  };
  const refusedValue = await setParam(99);
  check(old && Math.abs(refusedValue - old.paramValue) < 1e-6, `${speedId} = 99 (limit 15): refused, still ${refusedValue}`);

  // 9. Frames the vehicle must drop: another key, a replay, unsigned, garbage, a broken checksum.
  const armWrongKey = frame(commandLong(400, [1]), wrongKey);
  const noAck = collect('COMMAND_ACK', 1500, (d) => d.command === 400);
  sendRaw(armWrongKey);
  sendRaw(sent[sent.length - 1]);                              // the PARAM_SET again, byte for byte
  sendRaw(frame(commandLong(400, [1]), key, { signed: false })); // unsigned
  sendRaw(Buffer.from([0xfd, 0x09, 0x00, 0x00, 0x01, 0xff]));  // a truncated frame
  const broken = Buffer.from(frame(commandLong(400, [1])));
  broken[broken.length - 20] ^= 0xff;                          // a damaged byte: the checksum fails
  sendRaw(broken);
  sendRaw(Buffer.from('not mavlink at all'));
  check((await noAck).length === 0, 'arm with another key, a replayed frame, an unsigned arm, a truncated and a damaged frame: none acknowledged');
  const texts = report.statustexts.join(' | ');
  check(/bad signature/.test(texts) && /replayed/.test(texts) && /unsigned/.test(texts),
        'the vehicle said why: bad signature, replayed, unsigned');
  const hbNow = await waitFor('HEARTBEAT', (d, p) => p.header.compid === 1, 3000);
  check((hbNow.baseMode & 128) === 0, 'still disarmed');

  // 10. Arm, start the mission, every item reached, the landing. From now on, listen for the
  // change our GCS on LCM makes after the landing (it may come before this side sees the landing).
  const lcmParam = args['lcm-param'] ? args['lcm-param'].split('=') : null;
  let lcmParamSeen = false;
  if (lcmParam)
    listeners.add((n, d) => {
      if (n === 'PARAM_VALUE' && d.paramId === lcmParam[0] && Math.abs(d.paramValue - Number(lcmParam[1])) < 1e-6) lcmParamSeen = true;
    });
  const arm = await command(400, [1], 10000);
  check(arm.result === 0, `arm: COMMAND_ACK ${arm.result}${arm.progress.length ? `, progress ${arm.progress.join(' ')}` : ''}`);
  const reached = new Set();
  let inAir = false, landedAfterFlight = false, disarmed = false, maxRelAlt = 0;
  const watch = (n, d, p) => {
    if (n === 'MISSION_ITEM_REACHED') reached.add(d.seq);
    if (n === 'EXTENDED_SYS_STATE') { if (d.landedState === 2) inAir = true; if (inAir && d.landedState === 1) landedAfterFlight = true; }
    if (n === 'GLOBAL_POSITION_INT') maxRelAlt = Math.max(maxRelAlt, d.relativeAlt / 1000);
    if (n === 'HEARTBEAT' && p.header.compid === 1 && inAir && (d.baseMode & 128) === 0) disarmed = true;
  };
  listeners.add(watch);
  const start = await commandStarted(300, [0, 0]);
  check(start === 5 || start === 0, `mission start: COMMAND_ACK ${start} (5: IN_PROGRESS)`);
  const missionDone = waitFor('COMMAND_ACK', (d) => d.command === 300 && d.result !== 5, flightTimeoutS * 1000, 'the mission\'s end');
  let progressAcks = 0;
  const onProgress = (n, d) => { if (n === 'COMMAND_ACK' && d.command === 300 && d.result === 5) progressAcks++; };
  listeners.add(onProgress);
  const mode = await waitFor('HEARTBEAT', (d, p) => p.header.compid === 1 && (d.customMode >>> 16) === 0x0404, 10000, 'mission mode');
  check(mode, 'heartbeat: PX4 AUTO.MISSION while flying it');
  // In flight: a parameter change the vehicle takes at once.
  await sleep(3000);
  const newValue = await setParam(2.5);
  check(Math.abs(newValue - 2.5) < 1e-6, `${speedId} = 2.5 in flight: PARAM_VALUE ${newValue}`);
  // The camera: its information and the video stream QGroundControl would open.
  const camInfoP = waitFor('CAMERA_INFORMATION', null, 5000);
  check((await command(512, [259], 5000, 100)).result === 0, 'camera: CAMERA_INFORMATION requested from component 100');
  const camInfo = await camInfoP;
  const streamP = waitFor('VIDEO_STREAM_INFORMATION', null, 5000);
  check((await command(512, [269], 5000, 100)).result === 0, 'camera: VIDEO_STREAM_INFORMATION requested');
  const stream = await streamP;
  report.video = { width: stream.resolutionH, height: stream.resolutionV, uri: stream.uri, encoding: stream.encoding };
  check(stream.type === 1 && stream.encoding === 1 && stream.uri === '5600' && stream.resolutionH > 0 && (camInfo.flags & 256),
        `video: RTP/UDP H.264 on port ${stream.uri}, ${stream.resolutionH} x ${stream.resolutionV} at ${stream.framerate} Hz`);
  // This vehicle has no tracker (uav-demo's X650 carries the survey camera and the stereo pair):
  // the box is refused by the vehicle, saying why (tests/mavlink/qgc_commands.js tracks one).
  const track = await command(2005, [0.4, 0.4, 0.6, 0.6], 5000, 100);
  check(track.result === 2 && (camInfo.flags & 1024) === 0 && /no tracking camera/.test(report.statustexts.join(' | ')),
        `CAMERA_TRACK_RECTANGLE on a vehicle without a tracker: COMMAND_ACK ${track.result} (2: DENIED), the reason said`);
  const badBox = await command(2005, [0.6, 0.4, 0.4, 0.6], 5000, 100);
  check(badBox.result === 2, `a rectangle with its corners swapped: COMMAND_ACK ${badBox.result} (2: DENIED)`);
  const finalAck = await missionDone;
  const t1 = Date.now();
  while (!(landedAfterFlight && disarmed) && Date.now() - t1 < 60000) await sleep(200);
  listeners.delete(watch);
  listeners.delete(onProgress);
  check(finalAck.result === 0, `mission: final COMMAND_ACK ${finalAck.result} (0: ACCEPTED) after ${progressAcks} progress acks (IN_PROGRESS)`);
  const missing = items.map((_, i) => i).filter((i) => !reached.has(i));
  check(missing.length === 0, `MISSION_ITEM_REACHED for ${reached.size} of ${items.length} items${missing.length ? ` (missing ${missing.join(' ')})` : ''}`);
  check(maxRelAlt > 20 && landedAfterFlight && disarmed, `flew to ${maxRelAlt.toFixed(1)} m above home, landed and disarmed`);

  // 11. A change made by our GCS on LCM (after the landing) reaches this one as PARAM_VALUE.
  if (lcmParam) {
    const t2 = Date.now();
    while (!lcmParamSeen && Date.now() - t2 < 180000) await sleep(200);
    check(lcmParamSeen, `${lcmParam[0]} = ${lcmParam[1]} set by our GCS on LCM: seen here as PARAM_VALUE`);
  }

  // 12. Signing: every frame received.
  check(report.frames > 0 && report.unsigned === 0 && report.bad_signature === 0,
        `${report.frames} frames received, every one signed with the passphrase's key (${report.unsigned} unsigned, ${report.bad_signature} bad)`);
  report.items = items.length;
  report.reached = reached.size;
  if (args.report) fs.writeFileSync(args.report, JSON.stringify(report, null, 1));
  console.log(`qgc_client: ${report.checks.filter((c) => c.ok).length} of ${report.checks.length} checks held`);
  process.exit(process.exitCode || 0);
}

main().catch((e) => {
  console.error(`qgc_client: FAIL ${e.message}`);
  if (args.report) fs.writeFileSync(args.report, JSON.stringify(report, null, 1));
  process.exit(1);
});
