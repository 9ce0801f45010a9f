// Dividing (`divide N` on the board: the cutter off): the board's readout,
// from its status line while it divides, shown to be read from two metres:
// the way to the nearest division in large digits, green within a count,
// and a dial of the divisions with the spindle's mark on it.

const $ = (id) => document.getElementById(id);

// `+0.2` for `0.2`: the way to turn, signed (0 unsigned).
const signed = (v) => (v.startsWith('-') || /^[0.]*$/.test(v) ? v : `+${v}`);

// Degrees clockwise from the top, on a circle of radius r about (160, 160):
// the way the count goes up, as the readout's positive turn.
const at = (deg, r) => {
  const a = (deg * Math.PI) / 180;
  return [160 + r * Math.sin(a), 160 - r * Math.cos(a)].map((v) => v.toFixed(1));
};

// The dial: a tick for each division (up to 360 of them), the nearest
// one long and coloured, 0 marked, and the spindle's mark.
function drawDial(s, within) {
  const n = Number(s.divide);
  const nearest = Number(s.division);
  const colour = within ? '#070' : '#a40';
  let ticks = '';
  for (let k = 0; k < n && n <= 360; k++) {
    if (k === nearest) continue;
    const [x1, y1] = at((k * 360) / n, 130);
    const [x2, y2] = at((k * 360) / n, 150);
    ticks += `<line x1="${x1}" y1="${y1}" x2="${x2}" y2="${y2}" stroke="#567" stroke-width="2"/>`;
  }
  const [tx1, ty1] = at(Number(s.division_deg), 108);
  const [tx2, ty2] = at(Number(s.division_deg), 156);
  const [px, py] = at(Number(s.angle_deg), 120);
  $('divide-dial').innerHTML = `<circle cx="160" cy="160" r="150" fill="none" stroke="#ccd"/>${ticks}
    <line class="division" x1="${tx1}" y1="${ty1}" x2="${tx2}" y2="${ty2}" stroke="${colour}" stroke-width="6"/>
    <line class="spindle" x1="160" y1="160" x2="${px}" y2="${py}" stroke="#123" stroke-width="5" stroke-linecap="round"/>
    <circle cx="160" cy="160" r="8" fill="#123"/>
    <text x="160" y="44" text-anchor="middle" font-size="16">0</text>`;
}

// Shows the readout of status line `s` (its name=value pairs), or hides
// the view when the board is not dividing.
export function showDivide(s) {
  const view = $('divide-view');
  view.hidden = s.divide === undefined;
  if (view.hidden) return;
  const within = s.within === 'yes';
  view.dataset.within = within ? 'yes' : 'no';
  $('divide-division').textContent = `Division ${s.division} of ${s.divide} at ${s.division_deg}°`;
  $('divide-to').textContent = `${signed(s.to_deg)}°`;
  $('divide-counts').textContent = `${signed(s.to_counts)} counts to turn · ${within ? 'within ±1 count' : 'not there'}`;
  $('divide-angle').textContent = `spindle ${s.angle_deg}° ${s.angle_from === 'index'
    ? 'from the index' : 'from where the board started: turn past the index to fix the origin'}`;
  drawDial(s, within);
}
