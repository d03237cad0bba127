// The plan's mean path and risk ellipses from a PLAN_PATH datum, drawn as the
// ground's SVG map draws them (ground/plan_svg.cpp, ellipseElement): at mean
// t the covariance is start_cov + t process_sigma^2 I, and its ellipse is
// scaled by k = PhiInv(1 - risk_bound), the planner's own quantile
// (fsw/deliberative/gaussian.cpp, upperQuantile).

// Inverse of the standard normal CDF: Acklam's rational approximation,
// relative error below 1.2e-9, plenty for a drawing.
const A = [-3.969683028665376e1, 2.209460984245205e2, -2.759285104469687e2, 1.38357751867269e2, -3.066479806614716e1, 2.506628277459239];
const B = [-5.447609879822406e1, 1.615858368580409e2, -1.556989798598866e2, 6.680131188771972e1, -1.328068155288572e1];
const C = [-7.784894002430293e-3, -3.223964580411365e-1, -2.400758277161838, -2.549732539343734, 4.374664141464968, 2.938163982698783];
const D = [7.784695709041462e-3, 3.224671290700398e-1, 2.445134137142996, 3.754408661907416];

export function inverseNormal(p) {
  if (!(p > 0 && p < 1)) {
    return p === 0 ? -Infinity : p === 1 ? Infinity : NaN;
  }
  const low = 0.02425;
  if (p < low) {
    const q = Math.sqrt(-2 * Math.log(p));
    return (((((C[0] * q + C[1]) * q + C[2]) * q + C[3]) * q + C[4]) * q + C[5]) /
      ((((D[0] * q + D[1]) * q + D[2]) * q + D[3]) * q + 1);
  }
  if (p <= 1 - low) {
    const q = p - 0.5;
    const r = q * q;
    return ((((((A[0] * r + A[1]) * r + A[2]) * r + A[3]) * r + A[4]) * r + A[5]) * q) /
      (((((B[0] * r + B[1]) * r + B[2]) * r + B[3]) * r + B[4]) * r + 1);
  }
  const q = Math.sqrt(-2 * Math.log(1 - p));
  return -(((((C[0] * q + C[1]) * q + C[2]) * q + C[3]) * q + C[4]) * q + C[5]) /
    ((((D[0] * q + D[1]) * q + D[2]) * q + D[3]) * q + 1);
}

// k = PhiInv(1 - delta): how many sigmas the ellipses are.
export function upperQuantile(delta) {
  return -inverseNormal(delta);
}

function num(datum, key) {
  const v = Number(datum[key]);
  return Number.isFinite(v) ? v : undefined;
}

// The plan in a PLAN_PATH datum, or undefined when it holds no path.
export function planFromDatum(datum) {
  if (!datum) return undefined;
  const steps = num(datum, 'steps');
  if (!(steps >= 1)) return undefined;
  const means = [];
  for (let i = 0; i <= steps; i++) {
    const x = num(datum, `mean_x.${i}`);
    const y = num(datum, `mean_y.${i}`);
    if (x === undefined || y === undefined) break;
    means.push({ x, y });
  }
  if (means.length < 2) return undefined;
  return {
    planNumber: num(datum, 'plan_number'),
    steps: means.length - 1,
    means,
    startCov: [0, 1, 2, 3].map((i) => num(datum, `start_cov.${i}`) ?? 0),
    processSigma: num(datum, 'process_sigma') ?? 0,
    riskBound: num(datum, 'risk_bound'),
    riskUsed: num(datum, 'risk_used'),
    goal:
      num(datum, 'goal_x') !== undefined && num(datum, 'goal_y') !== undefined
        ? { x: num(datum, 'goal_x'), y: num(datum, 'goal_y') }
        : means[means.length - 1]
  };
}

// [{cx, cy, rx, ry, angleDeg}] in metres, one per mean; angleDeg is the major
// axis counter-clockwise from site x (y up). Empty without a usable risk bound.
export function riskEllipses(plan) {
  if (!plan || !(plan.riskBound > 0 && plan.riskBound < 0.5)) return [];
  const k = upperQuantile(plan.riskBound);
  const [c0, c1, c2, c3] = plan.startCov;
  const sigma2 = plan.processSigma * plan.processSigma;
  const out = [];
  plan.means.forEach((mean, t) => {
    const a = c0 + t * sigma2;
    const b = 0.5 * (c1 + c2);
    const d = c3 + t * sigma2;
    const mid = 0.5 * (a + d);
    const radius = Math.sqrt(0.25 * (a - d) * (a - d) + b * b);
    const major = Math.sqrt(Math.max(0, mid + radius));
    const minor = Math.sqrt(Math.max(0, mid - radius));
    const angleDeg = (0.5 * Math.atan2(2 * b, a - d) * 180) / Math.PI;
    const e = { cx: mean.x, cy: mean.y, rx: k * major, ry: k * minor, angleDeg };
    if (Object.values(e).every(Number.isFinite)) out.push(e);
  });
  return out;
}
