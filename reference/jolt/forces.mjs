// The environment's and the user's forces on the puppet, as core/src/environment.cpp and
// core/src/user_forces.cpp compute them, for the jolt engine, whose whole run is stepped here
// (docs/references.md, "The Jolt reference"). The same formulas in double precision; a test
// (tests/reference/jolt_test.cpp, "ForcesAgreeWithTheTestbeds") compares them with the C++ on
// the same states. Vectors are [x, y, z] arrays, quaternions [x, y, z, w].

export const kTrembleHz = 8.0;
export const kTrembleAmplitude = 0.003;
export const kStandardGravity = 9.81;

const add = (a, b) => [a[0] + b[0], a[1] + b[1], a[2] + b[2]];
const sub = (a, b) => [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
const scale = (s, a) => [s * a[0], s * a[1], s * a[2]];
const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
const cross = (a, b) => [
  a[1] * b[2] - a[2] * b[1],
  a[2] * b[0] - a[0] * b[2],
  a[0] * b[1] - a[1] * b[0],
];
const norm = (a) => Math.sqrt(dot(a, a));

// q·v·q⁻¹
export function rotate(q, v) {
  const [x, y, z, w] = q;
  const u = [x, y, z];
  const t = scale(2.0, cross(u, v));
  return add(add(v, scale(w, t)), cross(u, t));
}
export function conjugate(q) {
  return [-q[0], -q[1], -q[2], q[3]];
}

// the world's up (+z) in a body's frame: the third row of its rotation matrix
function upInFrame(q) {
  const [x, y, z, w] = q;
  return [2.0 * (x * z - w * y), 2.0 * (y * z + w * x), 1.0 - 2.0 * (x * x + y * y)];
}

function halfHeight(shape, up) {
  switch (shape.type) {
    case 'sphere':
      return shape.radius;
    case 'capsule':
      return Math.abs(up[2]) * shape.half_length + shape.radius;
    case 'box':
      return dot(up.map(Math.abs), shape.half_extents);
    case 'cylinder':
      return (
        Math.abs(up[2]) * shape.half_length +
        shape.radius * Math.sqrt(Math.max(0.0, 1.0 - up[2] * up[2]))
      );
    default:
      throw new Error(`shape "${shape.type}" has no height here`);
  }
}

// the segment's lowest and highest z (core: vertical_extent)
function verticalExtent(segment, q, x) {
  const up = upInFrame(q);
  if (segment.lone_shape) {
    const half = halfHeight(segment.shapes[0], up);
    return [x[2] - half, x[2] + half];
  }
  let below = -Infinity;
  let above = -Infinity;
  for (const shape of segment.shapes) {
    const centre = dot(shape.position, up);
    const half = halfHeight(shape, rotate(conjugate(shape.orientation), up));
    below = Math.max(below, half - centre);
    above = Math.max(above, half + centre);
  }
  return [x[2] - below, x[2] + above];
}

function submergedFraction(segment, environment, body) {
  if (!environment.water) return 0.0;
  const [low, high] = verticalExtent(segment, body.q, body.x);
  return Math.min(Math.max((environment.water_level - low) / (high - low), 0.0), 1.0);
}

// the rate that decays v by exactly e^(−c·h) over a step of h (core: step_drag_rate)
function stepDragRate(c, h) {
  return h > 0.0 && c !== 0.0 ? -Math.expm1(-c * h) / h : c;
}

// gravity, drag and buoyancy on one segment over a step of h (core: environment_wrench)
export function environmentWrench(segment, environment, body, h) {
  const f = submergedFraction(segment, environment, body);
  const g = environment.gravity;
  let drag;
  let force;
  if (!(f > 0.0)) {
    drag = stepDragRate(environment.air_drag, h);
    force = sub(scale(segment.mass, g), scale(drag * segment.mass, body.v));
  } else {
    drag = stepDragRate(environment.air_drag + environment.water_drag * f, h);
    force = sub(scale(segment.mass, g), scale(drag * segment.mass, body.v));
    force = sub(force, scale(environment.water_density * segment.volume * f, g));
  }
  let torque = [0, 0, 0];
  if (drag !== 0.0) {
    const wBody = rotate(conjugate(body.q), body.w);
    const iw = [segment.inertia[0] * wBody[0], segment.inertia[1] * wBody[1], segment.inertia[2] * wBody[2]];
    torque = scale(-drag, rotate(body.q, iw));
  }
  return { force, torque };
}

// a compliant pin's spring (core: pin_spring_wrench)
export function pinSpringWrench(pin, body) {
  const arm = rotate(body.q, pin.local_point);
  const force = scale(1.0 / pin.compliance, sub(pin.target, add(body.x, arm)));
  return { force, torque: cross(arm, force) };
}

// the 3×3 symmetric system K f = a, by its adjugate
function solveSymmetric3(k, a) {
  const [[a00, a01, a02], [, a11, a12], [, , a22]] = k;
  const c00 = a11 * a22 - a12 * a12;
  const c01 = a02 * a12 - a01 * a22;
  const c02 = a01 * a12 - a02 * a11;
  const c11 = a00 * a22 - a02 * a02;
  const c12 = a01 * a02 - a00 * a12;
  const c22 = a00 * a11 - a01 * a01;
  const det = a00 * c00 + a01 * c01 + a02 * c02;
  return [
    (c00 * a[0] + c01 * a[1] + c02 * a[2]) / det,
    (c01 * a[0] + c11 * a[1] + c12 * a[2]) / det,
    (c02 * a[0] + c12 * a[1] + c22 * a[2]) / det,
  ];
}

// R diag(d) Rᵀ for the body's rotation
function worldInverseInertia(segment, q) {
  const d = segment.inv_inertia;
  const e = [rotate(q, [1, 0, 0]), rotate(q, [0, 1, 0]), rotate(q, [0, 0, 1])];
  const out = [[0, 0, 0], [0, 0, 0], [0, 0, 0]];
  for (let i = 0; i < 3; ++i) {
    for (let j = 0; j < 3; ++j) {
      out[i][j] = e[0][i] * d[0] * e[0][j] + e[1][i] * d[1] * e[1][j] + e[2][i] * d[2] * e[2][j];
    }
  }
  return out;
}

// a grab's capped spring–damper at its point (core: grab_force)
export function grabForce(pin, segment, body) {
  const arm = rotate(body.q, pin.local_point);
  const point = add(body.x, arm);
  const pointVelocity = add(body.v, cross(body.w, arm));
  const omega = 2.0 * Math.PI * pin.grab.hz;
  // K = (1/m) E − [r]× I⁻¹ [r]×
  const c = [
    [0.0, -arm[2], arm[1]],
    [arm[2], 0.0, -arm[0]],
    [-arm[1], arm[0], 0.0],
  ];
  const inv = worldInverseInertia(segment, body.q);
  const k = [[0, 0, 0], [0, 0, 0], [0, 0, 0]];
  for (let i = 0; i < 3; ++i) {
    for (let j = 0; j < 3; ++j) {
      let s = 0.0;
      for (let a = 0; a < 3; ++a) {
        for (let b = 0; b < 3; ++b) s += c[i][a] * inv[a][b] * c[b][j];
      }
      k[i][j] = (i === j ? segment.inv_mass : 0.0) - s;
    }
  }
  const acceleration = sub(
    scale(omega * omega, sub(pin.target, point)),
    scale(2.0 * pin.grab.damping_ratio * omega, pointVelocity),
  );
  let force = solveSymmetric3(k, acceleration);
  const length = norm(force);
  if (length > pin.grab.max_force) force = scale(pin.grab.max_force / length, force);
  return force;
}

// splitmix64's finaliser, in 64-bit unsigned arithmetic (core: mix_bits)
const kMask = (1n << 64n) - 1n;
export function mixBits(x) {
  x = (x + 0x9e3779b97f4a7c15n) & kMask;
  x = ((x ^ (x >> 30n)) * 0xbf58476d1ce4e5b9n) & kMask;
  x = ((x ^ (x >> 27n)) * 0x94d049bb133111ebn) & kMask;
  return x ^ (x >> 31n);
}

function gradient(seed, lattice) {
  const bits = mixBits(seed ^ mixBits(BigInt.asUintN(64, BigInt(lattice))));
  return Number(bits >> 11n) * (2.0 / 9007199254740992.0) - 1.0;
}

// 1-D gradient noise in about [−½, ½] (core: gradient_noise)
export function gradientNoise(seed, t) {
  const cell = Math.floor(t);
  const f = t - cell;
  const g0 = gradient(seed, cell) * f;
  const g1 = gradient(seed, cell + 1) * (f - 1.0);
  const fade = f * f * f * (f * (f * 6.0 - 15.0) + 10.0);
  return g0 + fade * (g1 - g0);
}

// the seed's tremble on segment i (core: tremble_force); seed a BigInt
export function trembleForce(mass, i, body, time, pull, seed) {
  const omega = 2.0 * Math.PI * kTrembleHz;
  const acceleration = omega * omega * kTrembleAmplitude;
  const gamma = pull * norm(body.v);
  const size = mass * acceleration * Math.abs(Math.sin(gamma)) * Math.exp(-pull);
  if (size === 0.0) return [0, 0, 0];
  const gt = gamma * time;
  const sinc = Math.abs(gt) > 1e-8 ? Math.sin(gt) / gt : 1.0;
  const phase = kTrembleHz * time * (1.0 + 0.5 * sinc);
  const force = [0, 0, 0];
  for (let axis = 0; axis < 3; ++axis) {
    const key = mixBits((seed + 3n * BigInt(i) + BigInt(axis)) & kMask);
    force[axis] = 2.0 * size * gradientNoise(key, phase);
  }
  return force;
}

// the user's forces on every segment (core: user_wrenches): each grab at its point, and with
// environment.tremble the tremble; written over `out` (one {force, torque} per segment)
export function userWrenches(model, environment, pins, bodies, time, out) {
  for (let i = 0; i < out.length; ++i) out[i] = { force: [0, 0, 0], torque: [0, 0, 0] };
  let pull = 0.0;
  for (const pin of pins) {
    if (!(pin.grab.hz > 0.0)) continue;
    const segment = model.segments[pin.segment];
    const body = bodies[pin.segment];
    const force = grabForce(pin, segment, body);
    const w = out[pin.segment];
    w.force = add(w.force, force);
    w.torque = add(w.torque, cross(rotate(body.q, pin.local_point), force));
    pull += norm(force) / (segment.mass * kStandardGravity);
  }
  if (environment.tremble) {
    const seed = BigInt(environment.tremble_seed);
    for (let i = 0; i < model.segments.length; ++i) {
      const f = trembleForce(model.segments[i].mass, i, bodies[i], time, pull, seed);
      out[i].force = add(out[i].force, f);
    }
  }
  return pull;
}

// q·r, quaternions [x, y, z, w]
function multiply(q, r) {
  const [qx, qy, qz, qw] = q;
  const [rx, ry, rz, rw] = r;
  return [
    qw * rx + qx * rw + qy * rz - qz * ry,
    qw * ry - qx * rz + qy * rw + qz * rx,
    qw * rz + qx * ry - qy * rx + qz * rw,
    qw * rw - qx * rx - qy * ry - qz * rz,
  ];
}

// the rotation matrix of q, as rows
function matrix(q) {
  const columns = [rotate(q, [1, 0, 0]), rotate(q, [0, 1, 0]), rotate(q, [0, 0, 1])];
  return [0, 1, 2].map((r) => columns.map((c) => c[r]));
}
const mulMv = (m, v) => m.map((row) => dot(row, v));
const transpose = (m) => m[0].map((_, c) => m.map((row) => row[c]));
const mulMm = (a, b) => a.map((row) => transpose(b).map((col) => dot(row, col)));
const addM = (a, b) => a.map((row, r) => row.map((x, c) => x + b[r][c]));

// a 3×3 solve by Cramer's rule
function solve3(m, b) {
  const det = dot(m[0], cross(m[1], m[2]));
  const cols = transpose(m);
  const replaced = (k) => cols.map((c, i) => (i === k ? b : c));
  return [0, 1, 2].map((k) => {
    const r = transpose(replaced(k));
    return dot(r[0], cross(r[1], r[2])) / det;
  });
}
const identity = () => [unit(0), unit(1), unit(2)];
const inverse3 = (m) => transpose(identity().map((e) => solve3(m, e)));

// the rotation vector of q, shortest arc (core: quat_log)
function quatLog(q) {
  const sign = q[3] < 0.0 ? -1.0 : 1.0;
  const v = scale(sign, q.slice(0, 3));
  const s = norm(v);
  if (s === 0.0) return [0, 0, 0];
  return scale((2.0 * Math.atan2(s, sign * q[3])) / s, v);
}

const unit = (a) => [0, 1, 2].map((i) => (i === a ? 1 : 0));
const axisRotation = (a, angle) => {
  const half = 0.5 * angle;
  return [...scale(Math.sin(half), unit(a)), Math.cos(half)];
};

// the angles of R = R(a₀, θ₀) R(a₁, θ₁) R(a₂, θ₂) about three different axes, θ₁ within
// [−π/2, π/2] (core: euler_angles; a box's middle angle stays within ±85°, off the lock)
function eulerAngles(axes, q) {
  const [i, j, k] = axes;
  const m = matrix(q);
  const s = (j - i + 3) % 3 === 1 ? 1.0 : -1.0; // a cyclic order of x, y, z
  return [
    Math.atan2(-s * m[j][k], m[k][k]),
    Math.asin(Math.max(-1.0, Math.min(1.0, s * m[i][k]))),
    Math.atan2(-s * m[i][j], m[i][i]),
  ];
}

// row k: ∂θₖ/∂δ for a turn δ of q's own frame (core: euler_gradients)
function eulerGradients(axes, angles) {
  const last = conjugate(axisRotation(axes[2], angles[2]));
  const middle = conjugate(axisRotation(axes[1], angles[1]));
  const rates = transpose([
    rotate(last, rotate(middle, unit(axes[0]))),
    rotate(last, unit(axes[1])),
    unit(axes[2]),
  ]);
  return inverse3(rates);
}

// the joints' springs and dampers (core/src/joint_springs.cpp, add_joint_spring_wrenches) added
// to `out`, the damper implicit per joint over a step of h
export function addJointSpringWrenches(model, bodies, h, out) {
  for (const joint of model.joints) {
    if (joint.type === 'fixed') continue;
    const springs = joint.passive;
    if (springs.every((s) => s.stiffness === 0.0 && s.damping === 0.0)) continue;
    const parent = bodies[joint.parent];
    const child = bodies[joint.child];
    const fp = multiply(parent.q, joint.frame_in_parent);
    if (joint.type === 'slide') {
      // a force along the slide at each side's point, the damper implicit in the two masses
      const a = rotate(fp, joint.hinge_axis);
      const rp = rotate(parent.q, joint.anchor_in_parent);
      const rc = rotate(child.q, joint.anchor_in_child);
      const d = sub(add(child.x, rc), add(parent.x, rp));
      const dRate = sub(add(child.v, cross(child.w, rc)), add(parent.v, cross(parent.w, rp)));
      const s = springs[0];
      const inverse = model.segments[joint.parent].inv_mass + model.segments[joint.child].inv_mass;
      const rate = dot(a, dRate) + dot(cross(parent.w, a), d);
      const damping = s.damping / (1.0 + h * s.damping * inverse);
      const force = scale(-s.stiffness * (dot(a, d) - s.spring_ref) - damping * rate, a);
      out[joint.child].force = add(out[joint.child].force, force);
      out[joint.child].torque = add(out[joint.child].torque, cross(rc, force));
      out[joint.parent].force = sub(out[joint.parent].force, force);
      out[joint.parent].torque = sub(out[joint.parent].torque, cross(rp, force));
      continue;
    }
    const fc = multiply(child.q, joint.frame_in_child);
    let relative = multiply(conjugate(fp), fc);
    if (relative[3] < 0.0) relative = relative.map((x) => -x); // the same turn, w ≥ 0
    const omega = rotate(conjugate(fc), sub(child.w, parent.w));
    const inverseInertia = (segment, q) => {
      const r = matrix(q);
      return mulMm(
        r.map((row) => row.map((x, c) => x * segment.inv_inertia[c])),
        transpose(r),
      );
    };
    const rc = matrix(fc);
    const k = mulMm(
      mulMm(
        transpose(rc),
        addM(
          inverseInertia(model.segments[joint.parent], parent.q),
          inverseInertia(model.segments[joint.child], child.q),
        ),
      ),
      rc,
    );
    const implicit = (d, kk) => d / (1.0 + h * d * kk);
    let torque;
    if (joint.type === 'hinge') {
      const a = joint.hinge_axis;
      const angle = 2.0 * Math.atan2(dot(a, relative.slice(0, 3)), relative[3]); // w ≥ 0: ±π
      const s = springs[0];
      const damping = implicit(s.damping, dot(a, mulMv(k, a)));
      const f = -s.stiffness * (angle - s.spring_ref) - damping * dot(a, omega);
      torque = scale(f, a);
    } else if (joint.ball_limit === 'box') {
      const angles = eulerAngles(joint.box_order, relative);
      const g = eulerGradients(joint.box_order, angles);
      const rate = mulMv(g, omega);
      const f = [0, 1, 2].map((a) => {
        const s = springs[a];
        const ka = dot(g[a], mulMv(k, g[a]));
        return -s.stiffness * (angles[a] - s.spring_ref) - implicit(s.damping, ka) * rate[a];
      });
      torque = mulMv(transpose(g), f);
    } else {
      const s = springs[0];
      // the three rates together: ω' = (1 + h d K)⁻¹ ω, the damper's torque d ω'
      const hdk = k.map((row) => row.map((x) => h * s.damping * x));
      const rate = s.damping === 0.0 ? omega : solve3(addM(identity(), hdk), omega);
      torque = sub(scale(-s.stiffness, quatLog(relative)), scale(s.damping, rate));
    }
    const world = rotate(fc, torque);
    out[joint.child].torque = add(out[joint.child].torque, world);
    out[joint.parent].torque = sub(out[joint.parent].torque, world);
  }
}

// the world's joint on the root (core/src/joint_springs.cpp, add_root_spring_wrench) added to
// `out`: along each slide a force at the anchor, the damper implicit in the mass; about the hinge
// a torque, the damper implicit in the inertia about the hinge's line
function addRootSpringWrench(model, body, h, out) {
  const root = model.root;
  const segment = model.segments[0];
  const arm = rotate(body.q, root.anchor_in_root);
  const moved = sub(add(body.x, arm), root.anchor_world);
  const anchorVelocity = add(body.v, cross(body.w, arm));
  const implicit = (d, inverse) => d / (1.0 + h * d * inverse);
  for (let k = 0; k < root.passive.length; ++k) {
    const s = root.passive[k];
    if (s.stiffness === 0.0 && s.damping === 0.0) continue;
    const a = root.axes[k];
    if (k < root.slides) {
      const f =
        -s.stiffness * (dot(a, moved) - s.spring_ref) -
        implicit(s.damping, segment.inv_mass) * dot(a, anchorVelocity);
      out.force = add(out.force, scale(f, a));
      out.torque = add(out.torque, cross(arm, scale(f, a)));
    } else {
      let turn = multiply(body.q, conjugate(root.rest_orientation));
      if (turn[3] < 0.0) turn = turn.map((x) => -x);
      const angle = 2.0 * Math.atan2(dot(turn.slice(0, 3), a), turn[3]);
      const local = rotate(conjugate(body.q), a);
      const aboutCentre = dot(local, local.map((x, c) => x * segment.inertia[c]));
      const aboutLine = aboutCentre + segment.mass * dot(cross(a, arm), cross(a, arm));
      const f =
        -s.stiffness * (angle - s.spring_ref) - implicit(s.damping, 1.0 / aboutLine) * dot(a, body.w);
      out.torque = add(out.torque, scale(f, a));
    }
  }
}

// every segment's external wrench for a step of h from `bodies`: the environment's, the user's,
// the compliant pins' springs and the joints' springs and dampers
// (reference/src/pin_springs.h, PinSprings::wrenches)
export function allWrenches(model, environment, pins, bodies, time, h, user) {
  userWrenches(model, environment, pins, bodies, time, user);
  const applied = [];
  for (let s = 0; s < model.segments.length; ++s) {
    const w = environmentWrench(model.segments[s], environment, bodies[s], h);
    applied.push({ force: add(w.force, user[s].force), torque: add(w.torque, user[s].torque) });
  }
  for (const pin of pins) {
    if (pin.grab.hz > 0.0 || !(pin.compliance > 0.0)) continue;
    const pull = pinSpringWrench(pin, bodies[pin.segment]);
    const a = applied[pin.segment];
    a.force = add(a.force, pull.force);
    a.torque = add(a.torque, pull.torque);
  }
  addJointSpringWrenches(model, bodies, h, applied);
  if (model.root.hold !== 'free') addRootSpringWrench(model, bodies[0], h, applied[0]);
  return applied;
}
