// The pump's views are built by the server when the page first shows them (viewport.py). Each
// stands as a placeholder (CSS class `placeholder_class` and `view-<name>`) until then; when one
// comes within `margin` of a screen of what the tabs' pane shows of the browser's viewport (on a
// phone, what is above the controls' pane), its name joins the views seen, and the names seen so
// far are written into a hidden text input (CSS class `channel_class`), which the server reads. A placeholder that is not displayed (another tab is open) is not seen.
// Checked on every scroll and resize, and twice a second until every view is seen (a layout that
// moves without a scroll: a tab chosen, the sidebar collapsed, a view above grown). Runs once a
// page, on Bokeh's document_ready.
if (!window.__windpumpViewsSeen) {
  window.__windpumpViewsSeen = true
  const seen = new Set()
  let found = []

  const channel = () => {
    for (const doc of window.Bokeh.documents) {
      for (const model of doc.all_models) {
        if (Array.isArray(model.css_classes) && model.css_classes.includes(channel_class)) return model
      }
    }
    return null
  }

  const walk = (root, out) => {
    out.push(...root.querySelectorAll("." + placeholder_class))
    for (const el of root.querySelectorAll("*")) if (el.shadowRoot) walk(el.shadowRoot, out)
    return out
  }

  const nameOf = (el) => {
    const named = [...el.classList].find((c) => c.startsWith("view-") && c !== placeholder_class)
    return named == null ? null : named.slice("view-".length)
  }

  // While the server swaps placeholders for their views, the box holding them is laid out
  // again and is empty for a moment: the page would be shorter and the browser would scroll it
  // up. The box keeps its height until a second after the views have replaced them.
  const held = []
  const hold = (el) => {
    const place = el.getRootNode().host
    if (place == null) return
    if (!held.some((h) => h.place === place)) place.style.minHeight = `${place.getBoundingClientRect().height}px`
    held.push({el, place, since: null})
  }
  const release = () => {
    for (const h of held) {
      if (h.el.isConnected) continue
      if (h.since == null) h.since = Date.now()
      else if (Date.now() - h.since > 1000) h.done = true
    }
    for (const h of held) {
      if (h.done && held.every((other) => other.place !== h.place || other.done)) h.place.style.minHeight = ""
    }
    held.splice(0, held.length, ...held.filter((h) => !h.done))
  }

  const check = () => {
    if (found.length === 0 || found.some((el) => !el.isConnected)) found = walk(document, [])
    // What the tabs' pane shows of the screen: on a phone the controls' pane covers the rest
    // (page.NARROW_CSS), and a view behind it is not seen.
    const pane = document.querySelector("#main")?.getBoundingClientRect()
    const top = Math.max(0, pane?.top ?? 0), bottom = Math.min(window.innerHeight, pane?.bottom ?? Infinity)
    const reach = margin * window.innerHeight
    let more = false
    for (const el of found) {
      const name = nameOf(el)
      if (name == null || seen.has(name)) continue
      const box = el.getBoundingClientRect()
      if (box.width === 0 || box.height === 0) continue // not displayed
      if (box.top < bottom + reach && box.bottom > top - reach) {
        seen.add(name)
        more = true
        hold(el)
      }
    }
    release()
    if (more) {
      const model = channel()
      if (model != null) model.value = names.filter((name) => seen.has(name)).join(" ")
    }
    return names.every((name) => seen.has(name)) && held.length === 0
  }

  let pending = false
  const soon = () => {
    if (pending) return
    pending = true
    setTimeout(() => {
      pending = false
      check()
    }, 100)
  }
  document.addEventListener("scroll", soon, true) // capturing: the page's scrolling elements too
  window.addEventListener("resize", soon)
  const every = setInterval(() => {
    if (document.visibilityState === "visible" && check()) clearInterval(every)
  }, 500)
  check()
}
