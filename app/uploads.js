// A lab file larger than max_bytes is stopped in the browser, before Bokeh reads it and sends
// it: over ~15 MB the page's connection would close and the design on it would be lost. The
// server hears of the refusal through a hidden text input (CSS class `channel_class`) and says
// so next to the upload control. Runs once a page, on Bokeh's document_ready.
if (!window.__windpumpUploads) {
  window.__windpumpUploads = true

  const channel = () => {
    for (const doc of window.Bokeh.documents) {
      for (const model of doc.all_models) {
        if (Array.isArray(model.css_classes) && model.css_classes.includes(channel_class)) return model
      }
    }
    return null
  }

  const guard = (input) => {
    if (input.__windpumpGuarded) return
    input.__windpumpGuarded = true
    // On the input itself and capturing: runs before Bokeh's own listener, which it can stop.
    input.addEventListener(
      "change",
      (event) => {
        // A wind record or a site's weather (its upload's host carries `wind_class` or
        // `site_class`) may be larger than a lab file.
        const host = input.getRootNode().host
        const wind = host != null && host.classList.contains(wind_class)
        const site = host != null && host.classList.contains(site_class)
        const limit = wind || site ? wind_max_bytes : max_bytes
        const big = [...(input.files || [])].find((file) => file.size > limit)
        if (big == null) return
        event.stopImmediatePropagation()
        input.value = ""
        const model = channel()
        const kind = site ? "site" : wind ? "wind" : "lab"
        if (model != null) model.value = `${big.size}\t${Date.now()}\t${kind}\t${big.name}`
      },
      true,
    )
  }

  const walk = (root) => {
    root.querySelectorAll("input[type=file]").forEach(guard)
    for (const el of root.querySelectorAll("*")) if (el.shadowRoot) walk(el.shadowRoot)
  }
  walk(document)
  // A tab drawn later (the Wind tab's upload) calls this again once its content has arrived.
  window.__windpumpGuardAll = () => walk(document)
  // A file input drawn later is guarded before it can be used.
  for (const type of ["focusin", "pointerdown", "dragenter"]) {
    document.addEventListener(
      type,
      (event) => {
        const target = event.composedPath()[0]
        if (target instanceof HTMLInputElement && target.type === "file") guard(target)
      },
      true,
    )
  }
}
