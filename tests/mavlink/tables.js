// Checks our MAVLink tables (`uav-mavlink tables`) message by message against npm's
// mavlink-mappings, an independent generation of the same XML definitions: id, name, CRC_EXTRA,
// payload length, and each field's name, offset, size and whether it is an extension.
// Usage: node tables.js BIN_DIR
'use strict';
const { execFileSync } = require('child_process');
const path = require('path');
const mappings = require('mavlink-mappings');

const registry = { ...mappings.minimal.REGISTRY, ...mappings.standard.REGISTRY, ...mappings.common.REGISTRY };
const ours = JSON.parse(execFileSync(path.join(process.argv[2], 'uav-mavlink'), ['tables']).toString());
const sizes = { char: 1, int8_t: 1, uint8_t: 1, uint8_t_mavlink_version: 1, int16_t: 2, uint16_t: 2, int32_t: 4,
                uint32_t: 4, float: 4, int64_t: 8, uint64_t: 8, double: 8 };
let problems = 0;
const problem = (msg) => { console.error('MISMATCH ' + msg); problems++; };
for (const m of ours) {
  const theirs = registry[m.id];
  if (!theirs) { problem(`${m.name} (${m.id}): not in mavlink-mappings`); continue; }
  if (theirs.MSG_NAME !== m.name) problem(`${m.id}: name ${m.name}, theirs ${theirs.MSG_NAME}`);
  if (theirs.MAGIC_NUMBER !== m.crc_extra) problem(`${m.name}: CRC_EXTRA ${m.crc_extra}, theirs ${theirs.MAGIC_NUMBER}`);
  if (theirs.PAYLOAD_LENGTH !== m.length) problem(`${m.name}: length ${m.length}, theirs ${theirs.PAYLOAD_LENGTH}`);
  if (theirs.FIELDS.length !== m.fields.length)
    problem(`${m.name}: ${m.fields.length} fields, theirs ${theirs.FIELDS.length}`);
  theirs.FIELDS.forEach((f, i) => {
    const o = m.fields[i];
    if (!o) return;
    const type = f.type.replace(/\[\]$/, '');
    const size = sizes[type] * (f.length || 1);
    const want = `${f.source}@${f.offset}+${size}${f.extension ? ' ext' : ''}`;
    const got = `${o.name}@${o.offset}+${o.size}${o.extension ? ' ext' : ''}`;
    if (want !== got) problem(`${m.name} field ${i}: ours ${got}, theirs ${want}`);
  });
}
console.log(`tables.js: ${ours.length} messages compared with mavlink-mappings ` +
            `${require('mavlink-mappings/package.json').version}: ${problems} mismatches`);
process.exit(problems ? 1 : 0);
