// The machine's player, in the browser: it draws the run at a time from the frames the server sent
// once per run, with no server round trip per frame. Every CustomJS of the machine view runs this
// file's body, then one command: `play`, `scrub`, `reload` (a new run) or `show` (laid out).
// Changes are made with setv(..., {sync: false}): they redraw here and are never sent back.
const P = frames._player || (frames._player = {playing: false, t: 0, raf: 0, wall: null, drawn: 0})

function col(source, name) { return source.data[name] }

// The crank angle and volume at time t: cubic Hermite between frames, with the crank speed.
function state_at(t) {
  const T = col(frames, "t"), TH = col(frames, "theta"), W = col(frames, "theta_dot"), V = col(frames, "volume")
  const n = T.length
  if (n == 0) return null
  if (t <= T[0] || n == 1) return {theta: TH[0], volume: V[0]}
  if (t >= T[n - 1]) return {theta: TH[n - 1], volume: V[n - 1]}
  let lo = 0, hi = n - 1
  while (hi - lo > 1) { const mid = (lo + hi) >> 1; if (T[mid] <= t) lo = mid; else hi = mid }
  const h = T[hi] - T[lo], s = (t - T[lo]) / h
  const h00 = 2 * s ** 3 - 3 * s ** 2 + 1, h10 = s ** 3 - 2 * s ** 2 + s
  const h01 = -2 * s ** 3 + 3 * s ** 2, h11 = s ** 3 - s ** 2
  const theta = h00 * TH[lo] + h10 * h * W[lo] + h01 * TH[hi] + h11 * h * W[hi]
  return {theta, volume: V[lo] + s * (V[hi] - V[lo])}
}

// The piston's distance from TDC at a crank angle: the core's Eq. (1) table, interpolated.
function piston_x(theta) {
  const A = col(table, "theta"), X = col(table, "x"), n = A.length
  const a = ((theta % (2 * Math.PI)) + 2 * Math.PI) % (2 * Math.PI)
  const k = Math.min(n - 2, Math.floor(a / A[n - 1] * (n - 1)))
  const s = (a - A[k]) / (A[k + 1] - A[k])
  return X[k] + s * (X[k + 1] - X[k])
}

function draw(t) {
  const here = state_at(t)
  if (here == null) return
  const g = Object.fromEntries(Object.entries(geometry.data).map(([k, v]) => [k, v[0]]))
  const th = here.theta, rotor = g.R_dagger * th
  const xs = [], ys = [], colors = []
  for (let k = 0; k < 3; k++) {  // blades on the small sprocket's shaft, turning R+ times faster
    const a = rotor + 2 * Math.PI * k / 3
    xs.push([g.c0x, g.c0x - g.blade * Math.sin(a)]); ys.push([g.c0y, g.c0y + g.blade * Math.cos(a)])
  }
  xs.push([g.c0x, g.c0x - 0.8 * g.R0 * Math.sin(rotor)]); ys.push([g.c0y, g.c0y + 0.8 * g.R0 * Math.cos(rotor)])
  colors.push(...Array(4).fill("#6b6b6b"))
  // Cylinder k on its own throw, pitch * k to the right, sees the crank angle theta - 2 pi k / n.
  const n = g.cylinders || 1, joint = {x: [], y: []}, body = {x: [], y: [], width: [], height: []}
  let top0 = 0
  for (let k = 0; k < n; k++) {
    const phi = th - 2 * Math.PI * k / n, cx = k * (g.pitch || 0)
    const pin = [cx - g.R * Math.sin(phi), g.R * Math.cos(phi)]
    const top = g.L + g.R - piston_x(phi)  // piston pin height above the crank centre
    if (k == 0) top0 = top
    xs.push([cx, pin[0]]); ys.push([0, pin[1]]); colors.push("#d62728")  // crank
    xs.push([pin[0], cx]); ys.push([pin[1], top]); colors.push("#1f77b4")  // rod
    joint.x.push(pin[0], cx); joint.y.push(pin[1], top)
    body.x.push(cx); body.y.push(top + 0.4 * g.bore); body.width.push(g.bore); body.height.push(0.8 * g.bore)
  }
  links.setv({data: {xs, ys, color: colors}}, {sync: false})
  joints.setv({data: joint}, {sync: false})
  piston.setv({data: body}, {sync: false})
  const full = g.v_full > 0 ? Math.min(1, here.volume / g.v_full) : 0
  const depth = Math.max(full * g.tank_h, 1e-9)
  water.setv({data: {x: [g.tank_x + g.tank_w / 2], y: [g.tank_y + depth / 2], width: [g.tank_w], height: [depth]}}, {sync: false})
  label.setv({data: {x: [label.data.x[0]], y: [label.data.y[0]],
    text: [`t = ${t.toFixed(1)} s   V = ${(1e3 * here.volume).toFixed(1)} L`]}}, {sync: false})
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
