// The machine's player, in the browser: it draws the run at a time from the frames the server sent
// once per run, with no server round trip per frame. Every CustomJS of the machine view runs this
// file's body, then one command: `play`, `scrub`, `reload` (a new run) or `show` (laid out).
// The moving parts take the theme's colours from `palette` (machine.moving_colors).
// Changes are made with setv(..., {sync: false}): they redraw here and are never sent back.
const P = frames._player || (frames._player = {playing: false, t: 0, raf: 0, wall: null, drawn: 0})

function col(source, name) { return source.data[name] }

// Cubic Hermite between frames lo and hi = lo + 1 at fraction s, with the values' rates.
function hermite(values, rates, lo, h, s) {
  const h00 = 2 * s ** 3 - 3 * s ** 2 + 1, h10 = s ** 3 - 2 * s ** 2 + s
  const h01 = -2 * s ** 3 + 3 * s ** 2, h11 = s ** 3 - s ** 2
  return h00 * values[lo] + h10 * h * rates[lo] + h01 * values[lo + 1] + h11 * h * rates[lo + 1]
}

// The run at time t, from the core's frames: both angles by cubic Hermite with their speeds,
// the litres pumped and the tank's level linearly.
function state_at(t) {
  const T = col(frames, "t"), n = T.length
  if (n == 0) return null
  const TH = col(frames, "theta"), W = col(frames, "theta_dot"), V = col(frames, "litres")
  const ROTOR = col(frames, "rotor_angle"), RW = col(frames, "rotor_speed"), LEVEL = col(frames, "tank_level")
  const at = (k) => ({theta: TH[k], rotor: ROTOR[k], litres: V[k], level: LEVEL[k]})
  if (t <= T[0] || n == 1) return at(0)
  if (t >= T[n - 1]) return at(n - 1)
  let lo = 0, hi = n - 1
  while (hi - lo > 1) { const mid = (lo + hi) >> 1; if (T[mid] <= t) lo = mid; else hi = mid }
  const h = T[hi] - T[lo], s = (t - T[lo]) / h
  const linear = (X) => X[lo] + s * (X[hi] - X[lo])
  return {theta: hermite(TH, W, lo, h, s), rotor: hermite(ROTOR, RW, lo, h, s),
          litres: linear(V), level: linear(LEVEL)}
}

// Cylinder k's crank pin and piston pin at a crank angle: the core's table over one revolution
// (windpump.crank_table), interpolated.
function parts_at(theta, k) {
  const A = col(table, "theta"), n = A.length
  const a = ((theta % (2 * Math.PI)) + 2 * Math.PI) % (2 * Math.PI)
  const i = Math.min(n - 2, Math.floor(a / A[n - 1] * (n - 1)))
  const s = (a - A[i]) / (A[i + 1] - A[i])
  const at = (name) => { const X = col(table, name + k); return X[i] + s * (X[i + 1] - X[i]) }
  return {pin: [at("pin_x"), at("pin_y")], top: at("piston_y")}
}

function draw(t) {
  const here = state_at(t)
  if (here == null) return
  const g = Object.fromEntries(Object.entries(geometry.data).map(([k, v]) => [k, v[0]]))
  const th = here.theta, rotor = here.rotor
  const xs = [], ys = [], colors = []
  for (let k = 0; k < 3; k++) {  // blades on the small sprocket's shaft
    const a = rotor + 2 * Math.PI * k / 3
    xs.push([g.c0x, g.c0x - g.blade * Math.sin(a)]); ys.push([g.c0y, g.c0y + g.blade * Math.cos(a)])
  }
  xs.push([g.c0x, g.c0x - 0.8 * g.R0 * Math.sin(rotor)]); ys.push([g.c0y, g.c0y + 0.8 * g.R0 * Math.cos(rotor)])
  colors.push(...Array(4).fill(palette.blade))
  // Cylinder k stands pitch * k to the right, on its own throw.
  const n = g.cylinders || 1, joint = {x: [], y: []}, body = {x: [], y: [], width: [], height: []}
  let top0 = 0
  for (let k = 0; k < n; k++) {
    const cx = k * (g.pitch || 0), parts = parts_at(th, k)
    const pin = [cx + parts.pin[0], parts.pin[1]], top = parts.top
    if (k == 0) top0 = top
    xs.push([cx, pin[0]]); ys.push([0, pin[1]]); colors.push(palette.crank)  // crank
    xs.push([pin[0], cx]); ys.push([pin[1], top]); colors.push(palette.rod)  // rod
    joint.x.push(pin[0], cx); joint.y.push(pin[1], top)
    body.x.push(cx); body.y.push(top + 0.4 * g.bore); body.width.push(g.bore); body.height.push(0.8 * g.bore)
  }
  links.setv({data: {xs, ys, color: colors}}, {sync: false})
  joints.setv({data: joint}, {sync: false})
  piston.setv({data: body}, {sync: false})
  const depth = Math.max(here.level * g.tank_h, 1e-9)
  water.setv({data: {x: [g.tank_x + g.tank_w / 2], y: [g.tank_y + depth / 2], width: [g.tank_w], height: [depth]}}, {sync: false})
  label.setv({data: {x: [label.data.x[0]], y: [label.data.y[0]],
    text: [`t = ${t.toFixed(1)} s   V = ${here.litres.toFixed(1)} L`]}}, {sync: false})
  cursor.setv({data: {t: [t]}}, {sync: false})
  if (Math.abs(scrubber.value - t) > 1e-9) { P.from_player = true; scrubber.setv({value: t}, {sync: false}); P.from_player = false }
  P.t = t; P.drawn += 1; P.theta = th; P.top = top0
}

function end_time() { const T = col(frames, "t"); return T.length ? T[T.length - 1] : 0 }

function set_playing(on) {
  P.playing = on
  button.setv({label: on ? "▮▮ Pause" : "▶ Play"}, {sync: false})
  if (P.raf) { cancelAnimationFrame(P.raf); P.raf = 0 }
  P.wall = null
  if (on) P.raf = requestAnimationFrame(tick)
}

function tick(now) {
  P.raf = 0
  if (!P.playing) return
  if (P.wall == null) P.wall = now
  const elapsed = (now - P.wall) / 1000
  if (elapsed >= 1 / 30 - 1e-3) {  // 30 frames per second
    P.wall = now
    let t = P.t + elapsed * Number(speed_select.value)
    const end = end_time()
    if (t >= end) { draw(end); set_playing(false); return }
    draw(t)
  }
  P.raf = requestAnimationFrame(tick)
}

const origin = cb_obj.origin ?? cb_obj  // an event (the button's click) names its model as origin
const command = origin === button ? "play" : origin === scrubber ? "scrub" : origin === frames ? "reload"
  : origin === plot ? "show" : "speed"
if (command == "play") {
  if (!P.playing && P.t >= end_time()) draw(0)
  set_playing(!P.playing)
} else if (command == "scrub") {
  if (!P.from_player) draw(Number(scrubber.value))
} else if (command == "reload") {
  // A new run: stop, and show its start once the whole update has arrived.
  set_playing(false)
  setTimeout(() => { scrubber.setv({end: Math.max(end_time(), 1e-6)}, {sync: false}); draw(0) }, 0)
} else if (command == "show") {
  // First laid out (or resized): draw where the player stands.
  if (!P.playing) setTimeout(() => draw(Math.min(P.t, end_time())), 0)
}
