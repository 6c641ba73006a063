// The command service and the camera from a QGroundControl-style client (node-mavlink), on the
// simulated vehicle with a gimbal camera and the onboard tracker (the tracking scene): refusals
// first (take-off while disarmed, a mode this vehicle does not fly), then arm, take-off (the
// altitude above mean sea level, as QGroundControl sends it), DO_REPOSITION there and back,
// a target box on the video tracked onboard (CAMERA_TRACK_RECTANGLE) and released, Hold by
// DO_SET_MODE, and the landing with its disarm. Every frame received must be signed.
//
// Usage: node qgc_commands.js --passphrase TEXT [--port 14550 | --connect HOST:PORT] [--report FILE]
'use strict';
const fs = require('fs');
const {
  args, report, listeners, waitFor, sleep, check, command, listen, startHeartbeat, common,
} = require('./gcs_link');

const port = Number(args.port || 14550);
const R = 6378137;

async function main() {
  await listen(port);
  startHeartbeat();  // with --connect, the first heartbeat opens the link
  const hb = await waitFor('HEARTBEAT', (d, p) => p.header.compid === 1, 30000, 'the vehicle\'s HEARTBEAT');
  check(hb.autopilot === 12, 'heartbeat: PX4');
  let home = null;
  let at = null;  // [north, east, up] from home, metres
  listeners.add((n, d) => {
    if (n === 'GLOBAL_POSITION_INT' && home)
      at = [(d.lat * 1e-7 - home.lat) * Math.PI / 180 * R,
            (d.lon * 1e-7 - home.lon) * Math.PI / 180 * R * Math.cos(home.lat * Math.PI / 180), d.relativeAlt / 1000];
  });
  const homeP = waitFor('HOME_POSITION', null, 5000);
  await command(512, [242]);
  const h = await homeP;
  home = { lat: h.latitude * 1e-7, lon: h.longitude * 1e-7, alt: h.altitude * 1e-3 };
  // Ready to arm: SYS_STATUS's pre-arm bit healthy.
  await waitFor('SYS_STATUS', (d) => (d.onboardControlSensorsHealth & (1 << 28)) !== 0, 30000, 'the pre-arm checks');
  const waitAt = async (n, e, up, tolerance, ms, what) => {
    const t0 = Date.now();
    const near = () => at && Math.hypot(at[0] - n, at[1] - e) < tolerance && Math.abs(at[2] - up) < tolerance;
    while (!near() && Date.now() - t0 < ms) await sleep(100);
    check(near(), `${what}: at ${at ? at.map((v) => v.toFixed(1)).join(', ') : '?'} (north, east, up)`);
  };

  // Refusals: nothing moves.
  const early = await command(22, [0, 0, 0, NaN, NaN, NaN, home.alt + 6]);
  check(early.result === 2, `take-off while disarmed: COMMAND_ACK ${early.result} (2: DENIED)`);
  const acro = await command(176, [1, 5, 0]);
  check(acro.result === 3, `DO_SET_MODE to PX4 ACRO: COMMAND_ACK ${acro.result} (3: UNSUPPORTED)`);

  const start = [...at];  // where the vehicle stands (the simulator puts it near home, not on it)
  const arm = await command(400, [1]);
  check(arm.result === 0, `arm: COMMAND_ACK ${arm.result}`);
  const takeoff = await command(22, [0, 0, 0, NaN, NaN, NaN, home.alt + 6], 60000);
  check(takeoff.result === 0, `take-off to ${home.alt + 6} m above mean sea level (6 m up): COMMAND_ACK ${takeoff.result}` +
        ` after ${takeoff.progress.length} in progress`);
  await waitAt(start[0], start[1], 6, 0.7, 10000, 'above where it stood after the take-off');

  // DO_REPOSITION as COMMAND_INT (QGroundControl's "go to location"), altitude above home.
  const reposition = async (n, e) => {
    const c = new common.CommandInt();
    c.targetSystem = 1; c.targetComponent = 1; c.command = 192; c.frame = 6;
    // node-mavlink's COMMAND_INT: _param1.._param4, x and y as _param5 and _param6, z as _param7.
    c._param1 = -1; c._param2 = 1; c._param3 = 0; c._param4 = NaN;
    c._param5 = Math.round((home.lat + (n / R) * 180 / Math.PI) * 1e7);
    c._param6 = Math.round((home.lon + (e / (R * Math.cos(home.lat * Math.PI / 180))) * 180 / Math.PI) * 1e7);
    c._param7 = 6;
    const ack = waitFor('COMMAND_ACK', (d) => d.command === 192 && d.result !== 5, 60000, 'DO_REPOSITION\'s end');
    require('./gcs_link').send(c);
    return (await ack).result;
  };
  check((await reposition(3, 4)) === 0, 'DO_REPOSITION 3 m north, 4 m east: COMMAND_ACK 0');
  await waitAt(3, 4, 6, 0.7, 5000, 'after DO_REPOSITION');
  check((await reposition(0, 0)) === 0, 'DO_REPOSITION back over home: COMMAND_ACK 0');
  await waitAt(0, 0, 6, 0.7, 5000, 'back over home');

  // The camera: a box around the tent 30 m ahead (above the image centre at the gimbal's -20 deg).
  const infoP = waitFor('CAMERA_INFORMATION', null, 5000);
  await command(512, [259], 5000, 100);
  const info = await infoP;
  check((info.flags & 1024) !== 0 && (info.flags & 256) !== 0, `CAMERA_INFORMATION: video stream and tracking rectangle (flags ${info.flags})`);
  const track = await command(2005, [0.42, 0.22, 0.58, 0.40], 10000, 100);
  check(track.result === 0 && track.progress.length > 0,
        `CAMERA_TRACK_RECTANGLE around the tent: IN_PROGRESS, then COMMAND_ACK ${track.result} when the tracker has it`);
  await sleep(3000);
  check((await command(2010, [], 5000, 100)).result === 0, 'CAMERA_STOP_TRACKING: COMMAND_ACK 0');

  const hold = await command(176, [1, 4, 3]);
  const holdHb = await waitFor('HEARTBEAT', (d, p) => p.header.compid === 1 && d.customMode === 0x03040000, 5000, 'AUTO.LOITER');
  check(hold.result === 0 && holdHb, `DO_SET_MODE AUTO.LOITER (Hold): COMMAND_ACK ${hold.result}, heartbeat in Hold`);

  const land = await command(21, [], 60000);
  const down = await waitFor('HEARTBEAT', (d, p) => p.header.compid === 1 && (d.baseMode & 128) === 0, 30000, 'disarmed');
  check(land.result === 0 && down && at && at[2] < 0.3, `NAV_LAND: COMMAND_ACK ${land.result}, landed and disarmed`);

  check(report.frames > 0 && report.unsigned === 0 && report.bad_signature === 0,
        `${report.frames} frames received, every one signed (${report.unsigned} unsigned, ${report.bad_signature} bad)`);
  if (args.report) fs.writeFileSync(args.report, JSON.stringify(report, null, 1));
  console.log(`qgc_commands: ${report.checks.filter((c) => c.ok).length} of ${report.checks.length} checks held`);
  process.exit(process.exitCode || 0);
}

main().catch((e) => {
  console.error(`qgc_commands: FAIL ${e.message}`);
  process.exit(1);
});
