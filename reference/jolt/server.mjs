// The jolt engine's driver (docs/references.md, "The Jolt reference"): Jolt Physics' own
// WebAssembly build (the npm package jolt-physics, pinned in package.json), stepped by Node.js
// for the testbed's `jolt` engine (harness/src/engines/jolt.cpp), which starts it and speaks to
// it over stdin and stdout. A whole run is stepped here, so that no step waits for the testbed.
//
// Requests are one JSON line each; every answer is one JSON line, and an "advance" answer is
// followed by the bytes it announces:
//   {"op":"build", "model", "environment", "pins", "settings", "start", "time"}
//       builds the ragdoll in the state `start` (per segment x, q (x, y, z, w), v, ω, flat)
//   {"op":"advance", "dt", "steps", "targets"}
//       steps `steps` times; targets: each step's pin targets (world, flat), for its end
//       → {"ok":true, "steps":k, "diverged":bool, "bytes":b} and k records of float64, each
//         the state (13 per segment), the user's wrenches (6 per segment) and the step's
//         seconds inside Jolt
//   {"op":"forces", "states", "time", "h"}
//       the forces a step from each state would apply (the cross-check of forces.mjs)
//   {"op":"version"} → {"ok":true, "jolt":"1.1.0"}
//   {"op":"memory"} → {"ok":true, "used":bytes}: Jolt's heap in use (a driver must not grow)
// A request that fails answers {"error":"..."} and leaves the driver ready for the next.
import { createInterface } from 'node:readline';
import { readFileSync, writeSync } from 'node:fs';
import initJolt from 'jolt-physics/wasm-compat';
import { allWrenches } from './forces.mjs';

const Jolt = await initJolt();
const kPackage = JSON.parse(
  readFileSync(new URL('./node_modules/jolt-physics/package.json', import.meta.url)),
).version;

const kPuppetLayer = 0; // segments: they meet the ground only, never each other
const kGroundLayer = 1;
const kHandleLayer = 2; // the kinematic bodies that hard pins hang from: they meet nothing
const kRunaway = 1e6; // m/s or rad/s: a speed past it is a divergence, as in the other references

// Every object a build makes with `new` in Jolt's heap is let go when the build ends: a plain one
// destroyed, a reference-counted one (shape and constraint settings, which hold each other)
// released, so that Jolt frees it once nothing of its own holds it. A driver builds many worlds,
// and WebAssembly's heap does not shrink.
let temps = [];
let counted = [];
const own = (object) => {
  temps.push(object);
  return object;
};
const share = (object) => {
  object.AddRef();
  counted.push(object);
  return object;
};
function letGo() {
  for (const object of temps) Jolt.destroy(object);
  for (const object of counted) object.Release();
  temps = [];
  counted = [];
}
const v3 = (a) => own(new Jolt.Vec3(a[0], a[1], a[2]));
const r3 = (a) => own(new Jolt.RVec3(a[0], a[1], a[2]));
const quat = (q) => own(new Jolt.Quat(q[0], q[1], q[2], q[3]));
// a shape from its settings
const made = (settings) => own(settings.Create()).Get();

function rotate(q, v) {
  const [x, y, z, w] = q;
  const t = [2 * (y * v[2] - z * v[1]), 2 * (z * v[0] - x * v[2]), 2 * (x * v[1] - y * v[0])];
  return [
    v[0] + w * t[0] + (y * t[2] - z * t[1]),
    v[1] + w * t[1] + (z * t[0] - x * t[2]),
    v[2] + w * t[2] + (x * t[1] - y * t[0]),
  ];
}
const crossOf = (a, b) => [
  a[1] * b[2] - a[2] * b[1],
  a[2] * b[0] - a[0] * b[2],
  a[0] * b[1] - a[1] * b[0],
];
// a unit vector perpendicular to a unit `a`
function perpendicular(a) {
  const other = Math.abs(a[0]) < 0.9 ? [1, 0, 0] : [0, 1, 0];
  const p = crossOf(a, other);
  const n = Math.hypot(p[0], p[1], p[2]);
  return [p[0] / n, p[1] / n, p[2] / n];
}

// a fixed constraint's settings in the two bodies' COM frames: each body's point, and `in1`, `in2`
// taking the joint frame's axes into each body's frame
function fixed(point1, point2, in1, in2) {
  const s = share(new Jolt.FixedConstraintSettings());
  s.mSpace = Jolt.EConstraintSpace_LocalToBodyCOM;
  s.mPoint1 = r3(point1);
  s.mPoint2 = r3(point2);
  s.mAxisX1 = v3(in1([1, 0, 0]));
  s.mAxisY1 = v3(in1([0, 1, 0]));
  s.mAxisX2 = v3(in2([1, 0, 0]));
  s.mAxisY2 = v3(in2([0, 1, 0]));
  return s;
}

// Jolt's capsule and cylinder lie along y, the model's along z
const kZAlongY = [Math.SQRT1_2, 0, 0, Math.SQRT1_2]; // +90° about x takes y to z

function shapeSettings(shape) {
  switch (shape.type) {
    case 'sphere':
      return share(new Jolt.SphereShapeSettings(shape.radius));
    case 'box': {
      const e = shape.half_extents;
      // Jolt rounds a box's edges by its convex radius (default 5 cm) within the same extents
      const radius = Math.min(0.05, 0.5 * Math.min(e[0], e[1], e[2]));
      return share(new Jolt.BoxShapeSettings(v3(e), radius));
    }
    case 'capsule':
    case 'cylinder': {
      const inner =
        shape.type === 'capsule'
          ? new Jolt.CapsuleShapeSettings(shape.half_length, shape.radius)
          : new Jolt.CylinderShapeSettings(
              shape.half_length,
              shape.radius,
              Math.min(0.05, 0.5 * Math.min(shape.half_length, shape.radius)),
            );
      share(inner);
      return share(new Jolt.RotatedTranslatedShapeSettings(v3([0, 0, 0]), quat(kZAlongY), inner));
    }
    default:
      throw new Error(`shape "${shape.type}" has no Jolt shape`);
  }
}

// the segment's shapes as one Jolt shape whose centre of mass is the segment's origin
function segmentShape(segment) {
  let settings;
  if (segment.lone_shape) {
    settings = shapeSettings(segment.shapes[0]);
  } else {
    settings = share(new Jolt.StaticCompoundShapeSettings());
    for (const shape of segment.shapes) {
      // a capsule or cylinder inside a compound: its own rotation after the y-to-z turn
      const inner = shapeSettings({ ...shape, position: [0, 0, 0], orientation: [0, 0, 0, 1] });
      settings.AddShape(v3(shape.position), quat(shape.orientation), inner, 0);
    }
  }
  const shape = made(settings);
  const com = shape.GetCenterOfMass();
  const offset = [-com.GetX(), -com.GetY(), -com.GetZ()];
  if (offset.every((c) => c === 0)) return shape;
  return made(share(new Jolt.OffsetCenterOfMassShapeSettings(v3(offset), settings)));
}

class World {
  constructor(request) {
    try {
      this.build(request);
    } catch (error) {
      this.destroy();
      throw error;
    } finally {
      letGo();
    }
  }

  build(request) {
    const { model, environment, pins, settings } = request;
    this.model = model;
    this.environment = environment;
    this.pins = pins.map((p) => ({ ...p, target: [...p.target] }));
    this.time = request.time;

    const js = new Jolt.JoltSettings();
    const pairs = new Jolt.ObjectLayerPairFilterTable(3);
    pairs.EnableCollision(kPuppetLayer, kGroundLayer);
    const moving = own(new Jolt.BroadPhaseLayer(0));
    const still = own(new Jolt.BroadPhaseLayer(1));
    const broad = new Jolt.BroadPhaseLayerInterfaceTable(3, 2);
    broad.MapObjectToBroadPhaseLayer(kPuppetLayer, moving);
    broad.MapObjectToBroadPhaseLayer(kGroundLayer, still);
    broad.MapObjectToBroadPhaseLayer(kHandleLayer, moving);
    js.mObjectLayerPairFilter = pairs;
    js.mBroadPhaseLayerInterface = broad;
    // the three filters become the JoltInterface's, which deletes them
    js.mObjectVsBroadPhaseLayerFilter = new Jolt.ObjectVsBroadPhaseLayerFilterTable(
      broad,
      2,
      pairs,
      3,
    );
    this.jolt = new Jolt.JoltInterface(js);
    Jolt.destroy(js);
    const system = this.jolt.GetPhysicsSystem();
    system.SetGravity(v3([0, 0, 0])); // gravity is one of the environment's forces
    const physics = system.GetPhysicsSettings();
    physics.mNumVelocitySteps = settings.velocity_steps;
    physics.mNumPositionSteps = settings.position_steps;
    physics.mBaumgarte = settings.baumgarte;
    physics.mAllowSleeping = false;
    system.SetPhysicsSettings(physics);
    const bodies = system.GetBodyInterface();
    this.bodyInterface = bodies;

    const n = model.segments.length;
    this.bodies = [];
    for (let i = 0; i < n; ++i) {
      const segment = model.segments[i];
      const s = request.start.slice(13 * i, 13 * i + 13);
      const create = own(new Jolt.BodyCreationSettings(
        segmentShape(segment),
        r3(s.slice(0, 3)),
        quat(s.slice(3, 7)),
        Jolt.EMotionType_Dynamic,
        kPuppetLayer,
      ));
      create.mOverrideMassProperties = Jolt.EOverrideMassProperties_MassAndInertiaProvided;
      create.mMassPropertiesOverride.mMass = segment.mass;
      create.mMassPropertiesOverride.mInertia = Jolt.Mat44.prototype.sScaleVec3(v3(segment.inertia));
      create.mLinearDamping = 0.0; // Jolt: 0.05
      create.mAngularDamping = 0.0; // Jolt: 0.05
      create.mMaxLinearVelocity = kRunaway; // Jolt: 500 m/s
      create.mMaxAngularVelocity = kRunaway; // Jolt: 47 rad/s (a quarter turn per 1/60 s step)
      create.mApplyGyroscopicForce = true; // Jolt: off
      create.mAllowSleeping = false;
      create.mFriction = environment.friction; // combined with the ground's as √(μ·μ) = μ
      create.mRestitution = 0.0;
      create.mLinearVelocity = v3(s.slice(7, 10));
      create.mAngularVelocity = v3(s.slice(10, 13));
      const body = bodies.CreateBody(create);
      bodies.AddBody(body.GetID(), Jolt.EActivation_Activate);
      this.bodies.push(body);
    }

    if (environment.ground) {
      const create = own(new Jolt.BodyCreationSettings(
        made(share(new Jolt.BoxShapeSettings(v3([100, 100, 1]), 0.05))),
        r3([0, 0, -1]),
        quat([0, 0, 0, 1]),
        Jolt.EMotionType_Static,
        kGroundLayer,
      ));
      create.mFriction = environment.friction;
      create.mRestitution = 0.0;
      bodies.AddBody(bodies.CreateBody(create).GetID(), Jolt.EActivation_DontActivate);
    }

    for (const joint of model.joints) system.AddConstraint(this.joint(joint));
    if (model.root.hold !== 'free') system.AddConstraint(this.hold(model.root));

    // a hard pin: a point constraint to a kinematic handle moved onto each step's target
    this.handles = [];
    for (const pin of this.pins) {
      if (pin.grab.hz > 0.0 || pin.compliance > 0.0) {
        this.handles.push(null);
        continue;
      }
      const create = own(new Jolt.BodyCreationSettings(
        made(share(new Jolt.SphereShapeSettings(0.01))),
        r3(pin.target),
        quat([0, 0, 0, 1]),
        Jolt.EMotionType_Kinematic,
        kHandleLayer,
      ));
      create.mAllowSleeping = false;
      const handle = bodies.CreateBody(create);
      bodies.AddBody(handle.GetID(), Jolt.EActivation_Activate);
      const point = share(new Jolt.PointConstraintSettings());
      point.mSpace = Jolt.EConstraintSpace_LocalToBodyCOM;
      point.mPoint1 = r3([0, 0, 0]);
      point.mPoint2 = r3(pin.local_point);
      system.AddConstraint(point.Create(handle, this.bodies[pin.segment]));
      this.handles.push(handle);
    }
    this.user = new Array(n);
    this.identity = new Jolt.Quat(0, 0, 0, 1);
    this.scratch = new Jolt.Vec3(0, 0, 0);
    this.rscratch = new Jolt.RVec3(0, 0, 0);
  }

  // One model joint as a Jolt constraint, in the bodies' COM frames (the segment frames)
  joint(joint) {
    const parent = this.bodies[joint.parent];
    const child = this.bodies[joint.child];
    const inParent = (v) => rotate(joint.frame_in_parent, v);
    const inChild = (v) => rotate(joint.frame_in_child, v);
    const space = Jolt.EConstraintSpace_LocalToBodyCOM;
    if (joint.type === 'fixed') {
      const s = fixed(joint.anchor_in_parent, joint.anchor_in_child, inParent, inChild);
      return s.Create(parent, child);
    }
    if (joint.type === 'hinge' || joint.type === 'slide') {
      // a slide: Jolt's slider, its position the child's point less the parent's along the axis
      const hinge = joint.type === 'hinge';
      const normal = perpendicular(joint.hinge_axis);
      const s = share(new (hinge ? Jolt.HingeConstraintSettings : Jolt.SliderConstraintSettings)());
      s.mSpace = space;
      s.mPoint1 = r3(joint.anchor_in_parent);
      s.mPoint2 = r3(joint.anchor_in_child);
      s[hinge ? 'mHingeAxis1' : 'mSliderAxis1'] = v3(inParent(joint.hinge_axis));
      s.mNormalAxis1 = v3(inParent(normal));
      s[hinge ? 'mHingeAxis2' : 'mSliderAxis2'] = v3(inChild(joint.hinge_axis));
      s.mNormalAxis2 = v3(inChild(normal));
      if (hinge || joint.limited) {
        s.mLimitsMin = joint.lower;
        s.mLimitsMax = joint.upper;
      }
      return s.Create(parent, child);
    }
    if (joint.ball_limit === 'swing-twist') {
      // twist about the joint frame's z, the swing ellipse's axes its x and y: Jolt's plane axis
      // is x (its normal half-angle bounds the swing about x), its normal y
      const s = share(new Jolt.SwingTwistConstraintSettings());
      s.mSpace = space;
      s.mPosition1 = r3(joint.anchor_in_parent);
      s.mPosition2 = r3(joint.anchor_in_child);
      s.mTwistAxis1 = v3(inParent([0, 0, 1]));
      s.mPlaneAxis1 = v3(inParent([1, 0, 0]));
      s.mTwistAxis2 = v3(inChild([0, 0, 1]));
      s.mPlaneAxis2 = v3(inChild([1, 0, 0]));
      s.mSwingType = Jolt.ESwingType_Cone;
      s.mNormalHalfConeAngle = joint.swing_x;
      s.mPlaneHalfConeAngle = joint.swing_y;
      s.mTwistMinAngle = -joint.twist;
      s.mTwistMaxAngle = joint.twist;
      return s.Create(parent, child);
    }
    // An Euler box as Jolt's swing–twist pyramid (harness/src/engines/jolt_box.h): the frame and
    // ranges come from the testbed, which picks the reading nearer to the box, twist about a₂
    // (parent to child) or about a₀ (child to parent)
    const p = joint.pyramid;
    const unit = (k, sign = 1) => [k === 0 ? sign : 0, k === 1 ? sign : 0, k === 2 ? sign : 0];
    const [body1, body2, position1, position2, in1, in2] = p.twist_first
      ? [child, parent, joint.anchor_in_child, joint.anchor_in_parent, inChild, inParent]
      : [parent, child, joint.anchor_in_parent, joint.anchor_in_child, inParent, inChild];
    const s = share(new Jolt.SixDOFConstraintSettings());
    s.mSpace = space;
    s.mPosition1 = r3(position1);
    s.mPosition2 = r3(position2);
    s.mAxisX1 = v3(in1(unit(p.x)));
    s.mAxisY1 = v3(in1(unit(p.y, p.y_sign)));
    s.mAxisX2 = v3(in2(unit(p.x)));
    s.mAxisY2 = v3(in2(unit(p.y, p.y_sign)));
    s.mSwingType = Jolt.ESwingType_Pyramid;
    for (const t of ['TranslationX', 'TranslationY', 'TranslationZ']) {
      s.MakeFixedAxis(Jolt[`SixDOFConstraintSettings_EAxis_${t}`]);
    }
    ['RotationX', 'RotationY', 'RotationZ'].forEach((axis, k) =>
      s.SetLimitedAxis(Jolt[`SixDOFConstraintSettings_EAxis_${axis}`], p.lower[k], p.upper[k]),
    );
    return s.Create(body1, body2);
  }

  // The world's joint on the root as Jolt's own constraint to its fixed world body (at the origin,
  // unturned): a weld fixed, a hinge a hinge, a slide a slider, a ball a point, and a planar root a
  // six-degree-of-freedom constraint free along the two slides and about their plane's normal.
  // On the root's side in its COM frame from its rest pose, so that each coordinate is 0 there.
  hold(root) {
    const world = this.jolt.sGetFixedToWorldBody();
    const body = this.bodies[0];
    const [x, y, z, w] = root.rest_orientation;
    const inRoot = (v) => rotate([-x, -y, -z, w], v);
    const space = Jolt.EConstraintSpace_LocalToBodyCOM;
    const [a, b] = [root.axes[0], root.axes[1]];
    if (root.hold === 'weld') {
      return fixed(root.anchor_world, root.anchor_in_root, (v) => v, inRoot).Create(world, body);
    }
    if (root.hold === 'ball') {
      const s = share(new Jolt.PointConstraintSettings());
      s.mSpace = space;
      s.mPoint1 = r3(root.anchor_world);
      s.mPoint2 = r3(root.anchor_in_root);
      return s.Create(world, body);
    }
    if (root.hold === 'hinge' || root.hold === 'slide') {
      const hinge = root.hold === 'hinge';
      const s = share(new (hinge ? Jolt.HingeConstraintSettings : Jolt.SliderConstraintSettings)());
      const normal = perpendicular(a);
      s.mSpace = space;
      s.mPoint1 = r3(root.anchor_world);
      s.mPoint2 = r3(root.anchor_in_root);
      s[hinge ? 'mHingeAxis1' : 'mSliderAxis1'] = v3(a);
      s[hinge ? 'mHingeAxis2' : 'mSliderAxis2'] = v3(inRoot(a));
      s.mNormalAxis1 = v3(normal);
      s.mNormalAxis2 = v3(inRoot(normal));
      if (root.limited) {
        s.mLimitsMin = root.lower;
        s.mLimitsMax = root.upper;
      }
      return s.Create(world, body);
    }
    // planar: x and y along the slides, z across their plane
    const s = share(new Jolt.SixDOFConstraintSettings());
    s.mSpace = space;
    s.mPosition1 = r3(root.anchor_world);
    s.mPosition2 = r3(root.anchor_in_root);
    s.mAxisX1 = v3(a);
    s.mAxisY1 = v3(b);
    s.mAxisX2 = v3(inRoot(a));
    s.mAxisY2 = v3(inRoot(b));
    for (const axis of ['TranslationZ', 'RotationX', 'RotationY']) {
      s.MakeFixedAxis(Jolt[`SixDOFConstraintSettings_EAxis_${axis}`]);
    }
    for (const axis of ['TranslationX', 'TranslationY', 'RotationZ']) {
      s.MakeFreeAxis(Jolt[`SixDOFConstraintSettings_EAxis_${axis}`]);
    }
    return s.Create(world, body);
  }

  // every segment's state from Jolt, as {x, q, v, w}
  read() {
    const out = [];
    for (const body of this.bodies) {
      const x = body.GetCenterOfMassPosition();
      const q = body.GetRotation();
      const v = body.GetLinearVelocity();
      const w = body.GetAngularVelocity();
      // Jolt's single-precision quaternion is unit to its last bits: read as the unit one (the
      // testbed does the same operations on a state it places: jolt.cpp, unit_as_the_driver)
      const [qx, qy, qz, qw] = [q.GetX(), q.GetY(), q.GetZ(), q.GetW()];
      const n = Math.sqrt(qx * qx + qy * qy + qz * qz + qw * qw);
      out.push({
        x: [x.GetX(), x.GetY(), x.GetZ()],
        q: [qx / n, qy / n, qz / n, qw / n],
        v: [v.GetX(), v.GetY(), v.GetZ()],
        w: [w.GetX(), w.GetY(), w.GetZ()],
      });
    }
    return out;
  }

  // one step to the pins' `targets` (flat, world); false when the state left the finite
  step(dt, targets, record, at) {
    const states = this.read();
    for (let k = 0; k < this.pins.length; ++k) {
      this.pins[k].target = [targets[3 * k], targets[3 * k + 1], targets[3 * k + 2]];
    }
    const applied = allWrenches(
      this.model,
      this.environment,
      this.pins,
      states,
      this.time,
      dt,
      this.user,
    );
    for (const a of applied) {
      if (![...a.force, ...a.torque].every(Number.isFinite)) return false;
    }
    for (let k = 0; k < this.pins.length; ++k) {
      const handle = this.handles[k];
      if (!handle) continue;
      const t = this.pins[k].target;
      this.rscratch.Set(t[0], t[1], t[2]);
      this.bodyInterface.MoveKinematic(handle.GetID(), this.rscratch, this.identity, dt);
    }
    for (let i = 0; i < this.bodies.length; ++i) {
      const f = applied[i].force;
      const tq = applied[i].torque;
      this.scratch.Set(f[0], f[1], f[2]);
      this.bodies[i].AddForce(this.scratch);
      this.scratch.Set(tq[0], tq[1], tq[2]);
      this.bodies[i].AddTorque(this.scratch);
    }
    const begin = process.hrtime.bigint();
    this.jolt.Step(dt, 1);
    const seconds = Number(process.hrtime.bigint() - begin) * 1e-9;
    this.time += dt;
    const after = this.read();
    let offset = at;
    let ok = true;
    for (let i = 0; i < after.length; ++i) {
      const b = after[i];
      const values = [...b.x, ...b.q, ...b.v, ...b.w];
      for (const value of values) record[offset++] = value;
      if (!values.every(Number.isFinite)) ok = false;
      if (Math.hypot(...b.v) > kRunaway || Math.hypot(...b.w) > kRunaway) ok = false;
    }
    for (let i = 0; i < after.length; ++i) {
      const u = this.user[i];
      for (const value of [...u.force, ...u.torque]) record[offset++] = value;
    }
    record[offset] = seconds;
    return ok;
  }

  destroy() {
    for (const object of [this.jolt, this.identity, this.scratch, this.rscratch]) {
      if (object) Jolt.destroy(object);
    }
    this.jolt = null;
  }
}

let world = null;

function answer(header, payload) {
  const line = Buffer.from(JSON.stringify(header) + '\n');
  writeSync(1, line);
  if (payload) {
    const bytes = Buffer.from(payload.buffer, payload.byteOffset, payload.byteLength);
    let written = 0;
    while (written < bytes.length) written += writeSync(1, bytes, written);
  }
}

function handle(request) {
  switch (request.op) {
    case 'version':
      return answer({ ok: true, jolt: kPackage });
    case 'memory': {
      // the bytes of Jolt's heap in use: a driver must not grow build after build
      const heap = Jolt.JoltInterface.prototype;
      return answer({ ok: true, used: heap.sGetTotalMemory() - heap.sGetFreeMemory() });
    }
    case 'build':
      if (world) world.destroy();
      world = null;
      world = new World(request);
      return answer({ ok: true });
    case 'advance': {
      if (!world) throw new Error('advance before build');
      const n = world.bodies.length;
      const per = 19 * n + 1;
      const record = new Float64Array(per * request.steps);
      const width = 3 * world.pins.length;
      let done = 0;
      let diverged = false;
      while (done < request.steps) {
        const targets = request.targets.slice(width * done, width * (done + 1));
        const ok = world.step(request.dt, targets, record, per * done);
        ++done;
        if (!ok) {
          diverged = true;
          break;
        }
      }
      const payload = record.subarray(0, per * done);
      return answer({ ok: true, steps: done, diverged, bytes: payload.byteLength }, payload);
    }
    case 'forces': {
      const n = request.model.segments.length;
      const states = [];
      for (let i = 0; i < n; ++i) {
        const s = request.states.slice(13 * i, 13 * i + 13);
        states.push({ x: s.slice(0, 3), q: s.slice(3, 7), v: s.slice(7, 10), w: s.slice(10, 13) });
      }
      const user = new Array(n);
      const applied = allWrenches(
        request.model,
        request.environment,
        request.pins,
        states,
        request.time,
        request.h,
        user,
      );
      return answer({
        ok: true,
        applied: applied.flatMap((a) => [...a.force, ...a.torque]),
        user: user.flatMap((u) => [...u.force, ...u.torque]),
      });
    }
    default:
      throw new Error(`unknown request "${request.op}"`);
  }
}

const lines = createInterface({ input: process.stdin, crlfDelay: Infinity });
for await (const line of lines) {
  if (line.length === 0) continue;
  try {
    handle(JSON.parse(line));
  } catch (error) {
    world = null;
    answer({ error: String(error && error.message ? error.message : error).split('\n')[0] });
  }
}
