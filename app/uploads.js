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
        const big = [...(input.files || [])].find((file) => file.size > max_bytes)
        if (big == null) return
        event.stopImmediatePropagation()
        input.value = ""
        const model = channel()
        if (model != null) model.value = `${big.size}\t${Date.now()}\t${big.name}`
      },
      true,
    )
  }

  const walk = (root) => {
    root.querySelectorAll("input[type=file]").forEach(guard)
    for (const el of root.querySelectorAll("*")) if (el.shadowRoot) walk(el.shadowRoot)
  }
  walk(document)
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
