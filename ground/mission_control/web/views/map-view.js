// The rover map (Open MCT custom view of the "Map" object): in the site frame
// (x right, y up, metres) the site bounds and the rocks known from orbit
// (/api/map, COARSE_MAP), the hazards the rover has seen (HAZARDS), the plan
// in force, its mean path and risk ellipses (the latest PLAN_PATH), the goals
// (PLAN), the driven track (ROVER_STATE history and realtime) and the rover's
// pose with its position sigma. Every layer has a stable id and class
// (rse-map-*) for tests and styling.

import { html, svg, fixed, timeOfDay } from './dom.js';
import { PacketWatch } from '../lib/packet-watch.js';
import { planFromDatum, riskEllipses } from '../lib/risk-ellipses.js';
import { hazardFields } from '../lib/special-fields.js';

const DEFAULT_SITE = { x_min: -10, x_max: 10, y_min: -10, y_max: 10 };
const GRID_STEP_M = 5;
const TRACK_MIN_STEP_M = 0.02; // closer points add nothing visible

function finite(...values) {
  return values.every((v) => typeof v === 'number' && Number.isFinite(v));
}

function pointsAttribute(points) {
  return points.map((p) => `${p.x.toFixed(3)},${p.y.toFixed(3)}`).join(' ');
}

export class MapView {
  constructor(openmct, dictionary) {
    this.openmct = openmct;
    this.dictionary = dictionary;
    this.hazards = hazardFields(dictionary);
    this.watches = {}; // packet -> PacketWatch
    this.site = undefined;
    this.rocks = [];
    this.mapError = undefined;
  }

  show(element) {
    this.element = element;
    this.svg = svg('svg', {
      id: 'rse-map-svg',
      class: 'rse-map__svg',
      preserveAspectRatio: 'xMidYMid meet',
      role: 'img',
      'aria-label': 'Rover map'
    });
    // Geometry is drawn in metres inside a y-flipped group, so y is up.
    this.world = svg('g', { class: 'rse-map__world', transform: 'scale(1,-1)' });
    const layer = (name) => svg('g', { id: `rse-map-${name}`, class: `rse-map-${name}` });
    this.layers = {
      grid: layer('grid'),
      site: layer('site-layer'),
      rocks: layer('rocks'),
      hazards: layer('hazards'),
      ellipses: layer('ellipses'),
      goals: layer('goals'),
      rover: layer('rover-layer')
    };
    this.plan = svg('polyline', { id: 'rse-map-plan', class: 'rse-map-plan', points: '' });
    this.track = svg('polyline', { id: 'rse-map-track', class: 'rse-map-track', points: '' });
    this.world.append(
      this.layers.site,
      this.layers.grid,
      this.layers.rocks,
      this.layers.hazards,
      this.layers.ellipses,
      this.plan,
      this.layers.goals,
      this.track,
      this.layers.rover
    );
    this.labels = svg('g', { id: 'rse-map-labels', class: 'rse-map-labels' });
    this.svg.append(this.world, this.labels);
    this.status = html('div', { class: 'rse-map__status', id: 'rse-map-status' });
    element.append(
      html('div', { class: 'rse-map' }, [
        this.svg,
        html('div', { class: 'rse-map__legend' }, [
          this.#legendItem('rse-map-key--track', 'track'),
          this.#legendItem('rse-map-key--plan', 'plan (mean path, risk ellipses)'),
          this.#legendItem('rse-map-key--rock', 'rock (orbit)'),
          this.#legendItem('rse-map-key--hazard', this.hazards.present ? 'hazard seen' : 'hazards: no HAZARDS packet'),
          this.#legendItem('rse-map-key--rover', 'rover, 1σ')
        ]),
        this.status
      ])
    );
    this.#loadSite();
    this.#watch('ROVER_STATE', { mode: 'all' });
    this.#watch('PLAN_PATH', { mode: 'latest', wholeArchive: true });
    this.#watch('PLAN', { mode: 'latest' });
    if (this.hazards.present) this.#watch('HAZARDS', { mode: 'latest' });
    this.#draw();
  }

  destroy() {
    Object.values(this.watches).forEach((w) => w.stop());
    this.watches = {};
    cancelAnimationFrame(this.frame);
  }

  #legendItem(cls, text) {
    return html('span', { class: 'rse-map__key' }, [html('i', { class: `rse-map-key ${cls}` }), text]);
  }

  #watch(packet, options) {
    if (!this.dictionary.hasPacket(packet)) return;
    const watch = new PacketWatch(this.openmct, packet, { ...options, onChange: () => this.#scheduleDraw() });
    this.watches[packet] = watch;
    watch.start();
  }

  async #loadSite() {
    try {
      const response = await fetch('/api/map');
      if (!response.ok) throw new Error(`HTTP ${response.status}`);
      const map = await response.json();
      const s = map.site || {};
      if (finite(s.x_min, s.x_max, s.y_min, s.y_max) && s.x_max > s.x_min && s.y_max > s.y_min) {
        this.site = s;
      }
      this.rocks = Array.isArray(map.rocks) ? map.rocks : [];
    } catch (error) {
      this.mapError = `site map unavailable (${error.message})`;
    }
    this.#scheduleDraw();
  }

  #scheduleDraw() {
    cancelAnimationFrame(this.frame);
    this.frame = requestAnimationFrame(() => this.#draw());
  }

  // The site from /api/map, else a box around what there is to draw.
  #extent(trackPoints, plan) {
    if (this.site) return this.site;
    const points = [...trackPoints, ...(plan ? plan.means : [])];
    if (points.length === 0) return DEFAULT_SITE;
    const xs = points.map((p) => p.x);
    const ys = points.map((p) => p.y);
    return {
      x_min: Math.min(...xs) - 5,
      x_max: Math.max(...xs) + 5,
      y_min: Math.min(...ys) - 5,
      y_max: Math.max(...ys) + 5
    };
  }

  #trackPoints() {
    const points = [];
    for (const d of this.watches.ROVER_STATE?.datums || []) {
      if (d.estimate_valid === 0 || !finite(d.x, d.y)) continue;
      const last = points[points.length - 1];
      if (last && Math.hypot(d.x - last.x, d.y - last.y) < TRACK_MIN_STEP_M) continue;
      points.push({ x: d.x, y: d.y });
    }
    return points;
  }

  #draw() {
    const track = this.#trackPoints();
    const plan = planFromDatum(this.watches.PLAN_PATH?.latest);
    const site = this.#extent(track, plan);
    const width = site.x_max - site.x_min;
    const height = site.y_max - site.y_min;
    this.labelSize = 0.025 * Math.max(width, height);
    const margin = 0.5 * this.labelSize;
    const labelRoom = 3 * this.labelSize; // left of the site for the y labels, below it for x
    this.svg.setAttribute(
      'viewBox',
      [site.x_min - labelRoom, -site.y_max - margin, width + labelRoom + 3 * margin, height + labelRoom]
        .map((v) => v.toFixed(3))
        .join(' ')
    );

    this.#drawGrid(site);
    this.layers.site.replaceChildren(
      svg('rect', { id: 'rse-map-site', class: 'rse-map-site', x: site.x_min, y: site.y_min, width, height })
    );

    this.layers.rocks.replaceChildren(
      ...this.rocks
        .filter((r) => Array.isArray(r.points) && r.points.length >= 3)
        .map((r) =>
          svg('polygon', {
            class: 'rse-map-rock',
            'data-id': r.id,
            points: pointsAttribute(r.points.map(([x, y]) => ({ x, y })))
          })
        )
    );

    this.layers.hazards.replaceChildren(...this.#hazardCircles());

    this.plan.setAttribute('points', plan ? pointsAttribute(plan.means) : '');
    this.layers.ellipses.replaceChildren(
      ...riskEllipses(plan).map((e) =>
        svg('ellipse', {
          class: 'rse-map-ellipse',
          cx: e.cx.toFixed(3),
          cy: e.cy.toFixed(3),
          rx: e.rx.toFixed(3),
          ry: e.ry.toFixed(3),
          // In the y-up group SVG's rotation turns counter-clockwise, as the angle does.
          transform: `rotate(${e.angleDeg.toFixed(2)} ${e.cx.toFixed(3)} ${e.cy.toFixed(3)})`
        })
      )
    );
    this.layers.goals.replaceChildren(...this.#goalMarkers(plan));

    this.track.setAttribute('points', pointsAttribute(track));
    this.#drawRover();
    this.#drawStatus(plan, track);
  }

  #drawGrid(site) {
    const lines = [];
    const labels = [];
    const first = (v) => Math.ceil(v / GRID_STEP_M) * GRID_STEP_M;
    for (let x = first(site.x_min); x <= site.x_max; x += GRID_STEP_M) {
      lines.push(svg('line', { x1: x, x2: x, y1: site.y_min, y2: site.y_max }));
      labels.push(svg('text', { x, y: -site.y_min + this.labelSize * 1.4, 'font-size': this.labelSize, 'text-anchor': 'middle', text: `${x}` }));
    }
    for (let y = first(site.y_min); y <= site.y_max; y += GRID_STEP_M) {
      lines.push(svg('line', { x1: site.x_min, x2: site.x_max, y1: y, y2: y }));
      labels.push(svg('text', { x: site.x_min - this.labelSize * 0.3, y: -y + this.labelSize * 0.35, 'font-size': this.labelSize, 'text-anchor': 'end', text: `${y}` }));
    }
    this.layers.grid.replaceChildren(...lines);
    this.labels.replaceChildren(...labels);
  }

  #hazardCircles() {
    const d = this.watches.HAZARDS?.latest;
    const h = this.hazards;
    if (!d || !h.present) return [];
    const arrayLength = this.dictionary.arrayKeys('HAZARDS', h.x).length;
    const count = h.count !== undefined ? Math.min(Number(d[h.count]) || 0, arrayLength) : arrayLength;
    const circles = [];
    for (let i = 0; i < count; i++) {
      const x = d[`${h.x}.${i}`];
      const y = d[`${h.y}.${i}`];
      const r = h.radius ? d[`${h.radius}.${i}`] : 0.3;
      if (!finite(x, y, r) || r < 0) continue;
      circles.push(svg('circle', { class: 'rse-map-hazard', cx: x, cy: y, r: Math.max(r, 0.05) }));
    }
    return circles;
  }

  #goalMarkers(plan) {
    const markers = [];
    const marker = (x, y, cls) => {
      const s = this.labelSize * 0.5;
      return svg('path', {
        class: `rse-map-goal ${cls}`,
        d: `M ${x - s} ${y - s} L ${x + s} ${y + s} M ${x - s} ${y + s} L ${x + s} ${y - s}`
      });
    };
    const p = this.watches.PLAN?.latest;
    if (p) {
      const n = Number(p.goal_count) || 0;
      for (let i = 0; i < n; i++) {
        const x = p[`goal_x.${i}`];
        const y = p[`goal_y.${i}`];
        if (finite(x, y)) markers.push(marker(x, y, i === Number(p.goal_index) ? 'rse-map-goal--current' : ''));
      }
    }
    if (markers.length === 0 && plan) markers.push(marker(plan.goal.x, plan.goal.y, 'rse-map-goal--current'));
    return markers;
  }

  #drawRover() {
    const d = this.watches.ROVER_STATE?.latest;
    if (!d || !finite(d.x, d.y)) {
      this.layers.rover.replaceChildren();
      return;
    }
    const headingDeg = finite(d.heading) ? (d.heading * 180) / Math.PI : 0;
    const sigma = finite(d.position_sigma) ? d.position_sigma : 0;
    const size = Math.max(0.5, this.labelSize * 0.8);
    this.layers.rover.replaceChildren(
      svg('g', { id: 'rse-map-rover', class: 'rse-map-rover', transform: `translate(${d.x.toFixed(3)} ${d.y.toFixed(3)})` }, [
        svg('circle', { class: 'rse-map-rover__sigma', r: Math.max(sigma, 0).toFixed(3) }),
        svg('polygon', {
          class: 'rse-map-rover__body',
          transform: `rotate(${headingDeg.toFixed(2)})`,
          points: `${size},0 ${-0.6 * size},${0.5 * size} ${-0.6 * size},${-0.5 * size}`
        })
      ])
    );
  }

  #drawStatus(plan, track) {
    const parts = [];
    if (this.mapError) parts.push(this.mapError);
    const pose = this.watches.ROVER_STATE?.latest;
    parts.push(
      pose && finite(pose.x, pose.y)
        ? `rover (${fixed(pose.x, 2)}, ${fixed(pose.y, 2)}) m, heading ${fixed((pose.heading * 180) / Math.PI, 0)}°, σ ${fixed(pose.position_sigma, 2)} m at ${timeOfDay(pose.utc)}`
        : 'no rover state in the window'
    );
    parts.push(`track ${track.length} points`);
    parts.push(
      plan
        ? `plan #${plan.planNumber ?? '?'}: ${plan.steps} steps, risk bound ${plan.riskBound?.toExponential(1)}, used ${plan.riskUsed?.toExponential(1)}`
        : 'no plan'
    );
    if (this.hazards.present) parts.push(`hazards ${this.layers.hazards.childElementCount}`);
    this.status.textContent = parts.join(' · ');
  }
}

export function mapViewProvider(openmct, state, type) {
  return {
    key: 'rse.map-view',
    name: 'Map',
    cssClass: 'icon-image',
    canView: (domainObject) => domainObject.type === type,
    view: () => new MapView(openmct, state.dictionary)
  };
}
