#!/usr/bin/env node
/*
 * cncjs's G-code reader as a peer of our writers (tests/test_convert_peers.py).
 *
 * usage: NODE_PATH=/tmp/peers/node_modules node tests/peers/toolpath.js FILE...
 *
 * Every line of every FILE goes through gcode-parser's parseLine (the grammar check) and
 * through one gcode-toolpath interpreter per file (G0/G1/G2/G3 with IJK or R in G17/G18/
 * G19, G90/G91, G20/G21, G92). Printed, one JSON object per line:
 *   {"file": i, "line": n, "reject": "..."}         a block the parser does not read whole
 *   {"file": i, "line": n, "kind": "line"|"arc", "motion": "G1", "plane": "G17",
 *    "start": [x, y, z], "end": [x, y, z], "centre": [x, y, z]}   a motion callback
 *   {"file": i, "blocks": n}                         the file's number of non-empty lines
 * Positions are gcode-toolpath's: millimetres, program coordinates plus its G92 offset;
 * arc points are given back in X, Y, Z order (gcode-toolpath rotates them into its plane).
 */
'use strict';

const fs = require('fs');
const { parseLine } = require('gcode-parser');
const Toolpath = require('gcode-toolpath');

// gcode-toolpath hands arc points over as (first, second, normal) of the plane
const UNROTATE = {
  G17: (v) => [v.x, v.y, v.z],
  G18: (v) => [v.y, v.z, v.x], // it passes (z, x, y)
  G19: (v) => [v.z, v.x, v.y], // it passes (y, z, x)
};

function out(obj) {
  process.stdout.write(JSON.stringify(obj) + '\n');
}

// A block is read whole when every letter starts a numeric word the parser returned.
function grammarProblem(text, parsed) {
  let stripped = '';
  let depth = 0;
  for (const ch of text) {
    if (ch === ';' && depth === 0) break;
    if (ch === '(') depth += 1;
    else if (ch === ')') depth = Math.max(0, depth - 1);
    else if (depth === 0) stripped += ch;
  }
  if (depth !== 0) return 'unclosed comment';
  const letters = (stripped.match(/[A-Za-z]/g) || []).length;
  const words = parsed.words.length + (parsed.ln === undefined ? 0 : 1);
  const bad = parsed.words.filter((w) => typeof w[1] !== 'number');
  if (bad.length) return 'non-numeric word ' + bad.map((w) => w.join('')).join(' ');
  if (letters !== words) return `${letters} letters but ${words} words read`;
  return null;
}

function runFile(index, path) {
  let line = 0;
  const record = (kind) => (modal, v1, v2, v0) => {
    const un = kind === 'arc' ? UNROTATE[modal.plane] : UNROTATE.G17;
    const rec = { file: index, line, kind, motion: modal.motion, plane: modal.plane };
    rec.start = un(v1);
    rec.end = un(v2);
    if (kind === 'arc') rec.centre = un(v0);
    out(rec);
  };
  const toolpath = new Toolpath({ addLine: record('line'), addArcCurve: record('arc') });
  const lines = fs.readFileSync(path, 'utf8').split(/\r?\n/);
  let blocks = 0;
  for (const text of lines) {
    line += 1;
    if (text.trim() === '') continue;
    blocks += 1;
    const problem = grammarProblem(text, parseLine(text, { flatten: false }));
    if (problem) out({ file: index, line, reject: problem });
    toolpath.loadFromStringSync(text);
  }
  out({ file: index, blocks });
}

process.argv.slice(2).forEach((path, i) => runFile(i, path));
