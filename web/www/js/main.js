// The page: five views over one setup. Each view is its own module.
import { load } from './polyturn.js';
import * as plan from './plan.js';
import * as preview from './preview.js';
import * as simulate from './simulate.js';
import * as device from './device.js';
import * as flash from './flash.js';

export function show(tab) {
  for (const b of document.querySelectorAll('nav button')) b.classList.toggle('active', b.dataset.tab === tab);
  for (const s of document.querySelectorAll('.tab')) s.classList.toggle('active', s.id === tab);
}

for (const b of document.querySelectorAll('nav button')) b.addEventListener('click', () => show(b.dataset.tab));

await load();
plan.init({ show });
preview.init();
simulate.init();
device.init();
await flash.init();
document.getElementById('loading').textContent = '';
document.body.dataset.ready = 'yes';
