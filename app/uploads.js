// A lab file larger than max_bytes is stopped in the browser, before Bokeh reads it and sends
// it: over ~15 MB the page's connection would close and the design on it would be lost. The
// server hears of the refusal through a hidden text input (CSS class `channel_class`) and says
// so next to the upload control. A wind record or a site's weather file (up to wind_max_bytes)
// is posted by HTTP to `upload_url` instead of going over the websocket as one ~13 MB message
// (app/server/upload_route.py), and the same input carries its reference: "sending", then "posted <id>"
// once the server holds it, or "failed <reason>"; an empty file is "empty" (nothing to send).
// The server takes a file only from a page whose websocket is open, this page's session id in
// the header `session_header`.
// Without `upload_url` (a server without the route), or when the route answers 404, the file
// goes Bokeh's way. Runs once a page, on Bokeh's document_ready.
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
  const tell = (file, kind, state) => {
    const model = channel()
    const name = file.name.replace(/[\t\n\r]/g, " ")
    const value = `${file.size}\t${Date.now()}\t${kind}\t${name}`
    if (model != null) model.value = state ? `${value}\t${state}` : value
  }

  // The posts under way, by kind: a later file of the same upload cancels an earlier one.
  const posting = {}
  const post = (input, file, kind) => {
    if (posting[kind] != null) posting[kind].abort()
    const controller = new AbortController()
    posting[kind] = controller
    tell(file, kind, "sending")
    const query = new URLSearchParams({kind: kind, name: file.name})
    fetch(`${upload_url}?${query}`, {
      method: "POST",
      body: file,
      // The session's id is the post's credential: in a header, not in a URL a log keeps.
      headers: {"Content-Type": "application/octet-stream", [session_header]: session_id},
      signal: controller.signal,
    })
      .then(async (response) => {
        if (response.status === 404 || response.status === 405) {
          bokehs_way(input)  // an older server: no route
          return
        }
        const answer = await response.json().catch(() => ({}))
        if (controller.signal.aborted) return
        if (response.ok && answer.id) tell(file, kind, `posted ${answer.id}`)
        else tell(file, kind, `failed ${answer.refused || "network"}`)
      })
      .catch((error) => {
        if (error.name !== "AbortError") tell(file, kind, "failed network")
      })
      .finally(() => {
        if (posting[kind] === controller) posting[kind] = null
      })
  }
  // The change again, for Bokeh's own listener (which sends the file over the websocket).
  const bokehs_way = (input) => {
    input.__windpumpBokeh = true
    try {
      input.dispatchEvent(new Event("change"))
    } finally {
      input.__windpumpBokeh = false
    }
  }

  const guard = (input) => {
    if (input.__windpumpGuarded) return
    input.__windpumpGuarded = true
    // On the input itself and capturing: runs before Bokeh's own listener, which it can stop.
    input.addEventListener(
      "change",
      (event) => {
        if (input.__windpumpBokeh) return
        // A wind record or a site's weather (its upload's host carries `wind_class` or
        // `site_class`) may be larger than a lab file.
        const host = input.getRootNode().host
        const wind = host != null && host.classList.contains(wind_class)
        const site = host != null && host.classList.contains(site_class)
        const limit = wind || site ? wind_max_bytes : max_bytes
        const kind = site ? "site" : wind ? "wind" : "lab"
        const big = [...(input.files || [])].find((file) => file.size > limit)
        if (big != null) {
          event.stopImmediatePropagation()
          input.value = ""
          tell(big, kind, "")
          return
        }
        const file = (input.files || [])[0]
        if (kind === "lab" || !upload_url || file == null) return
        event.stopImmediatePropagation()
        if (file.size === 0) tell(file, kind, "empty")
        else post(input, file, kind)
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
