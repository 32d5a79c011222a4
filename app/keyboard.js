// Keyboard and screen readers, where Bokeh 3.9's widgets and Panel's template fall short: tab
// headers are focusable but do not react to keys and carry no role; slider handles have no
// accessible name, and say their value to one decimal (aria-valuenow 3.8 where the page shows
// 3.75) without its unit; a check box's text is not its label; the template's sidebar is a <ul>
// of <div>s. Listens on the document (events from the widgets' shadow DOM reach it), and
// annotates again whenever the server changes the page, so widgets drawn later (a tab, a card,
// a view built when first seen) are covered too. Runs once a page, on Bokeh's document_ready,
// with `unit_words` (keyboard.UNIT_WORDS): a unit's symbol -> [its word for 1, for any other].
if (!window.__windpumpKeyboard) {
  window.__windpumpKeyboard = true

  const everywhere = (root, selector, found = []) => {
    found.push(...root.querySelectorAll(selector))
    for (const el of root.querySelectorAll("*")) {
      if (el.shadowRoot) everywhere(el.shadowRoot, selector, found)
    }
    return found
  }

  // A slider's handle takes its label ("Head h [m]") from the title above it, without the value
  // (the handle already says its value through aria-valuetext).
  const labelOf = (handle) => {
    const title = handle.getRootNode().querySelector(".bk-slider-title")
    if (title == null) return ""
    const first = title.firstChild
    const text = first != null && first.nodeType === Node.TEXT_NODE ? first.textContent : title.textContent
    return text.replace(/:\s*$/, "").trim()
  }
  const nameHandle = (handle) => {
    const label = labelOf(handle)
    if (label) handle.setAttribute("aria-label", label)
  }

  // What a screen reader says of a slider's value: the value as the page shows it (the handle's
  // tooltip, Bokeh's format) and its unit in words, from the label's brackets ("Head h [m]":
  // "3.1 metres"); aria-valuenow the same number, aria-valuemin and -max the slider's ends (noUi
  // writes all three to one decimal). A unit without words (keyboard.UNIT_WORDS) is said as
  // written. Set after each of noUi's own updates of them.
  const unitOf = (handle) => {
    const found = /\[([^\]]+)\]/.exec(labelOf(handle))
    return found == null ? null : found[1]
  }
  const sayValue = (handle, range) => {
    const tooltip = handle.querySelector(".noUi-tooltip")
    const value = handle.getRootNode().querySelector(".bk-slider-value")
    const shown = (tooltip ?? value)?.textContent.trim()
    if (!shown) return
    const number = Number(shown.replace(/,/g, ""))
    const unit = unitOf(handle)
    const words = unit == null ? null : unit_words[unit]
    const spoken = words == null ? unit : words[shown === "1" ? 0 : 1]
    handle.setAttribute("aria-valuetext", spoken == null ? shown : `${shown} ${spoken}`)
    if (Number.isFinite(number)) handle.setAttribute("aria-valuenow", String(number))
    handle.setAttribute("aria-valuemin", String(range.min))
    handle.setAttribute("aria-valuemax", String(range.max))
  }
  const speakValues = (target) => {
    const slider = target.noUiSlider
    if (slider == null || slider.__windpumpSpoken) return
    slider.__windpumpSpoken = true
    // after every other handler of the move: noUi's own, and the tooltip's (which noUi binds
    // again, after this one, whenever Bokeh updates the slider's options)
    slider.on("update.windpumpSpoken", (_values, index) =>
      setTimeout(() => {
        const handle = target.querySelectorAll(".noUi-handle")[index]
        if (handle != null) sayValue(handle, slider.options.range)
      }, 0),
    )
  }

  // A check box's text beside it is its label (Bokeh draws it as a <div>, not a <label>).
  const labelCheckbox = (box) => {
    const text = box.nextElementSibling
    if (text == null || !text.classList.contains("bk-label") || box.hasAttribute("aria-labelledby")) return
    text.id = text.id || "checkbox-label"
    box.setAttribute("aria-labelledby", text.id)
  }

  // The template's sidebar and main area are <ul>s holding Bokeh's roots (<div>s), not a list
  // of items: no list to a screen reader.
  const unlist = () => {
    for (const list of document.querySelectorAll("ul")) {
      if ([...list.children].some((child) => child.tagName !== "LI")) list.setAttribute("role", "none")
    }
  }

  const markTabs = (list) => {
    list.setAttribute("role", "tablist")
    for (const tab of list.children) {
      tab.setAttribute("role", "tab")
      tab.setAttribute("aria-selected", String(tab.classList.contains("bk-active")))
    }
  }

  const annotate = () => {
    const found = everywhere(document, ".noUi-handle, .noUi-target, input[type=checkbox], .bk-tab")
    const having = (selector) => found.filter((el) => el.matches(selector))
    having(".noUi-handle").forEach(nameHandle)
    having(".noUi-target").forEach(speakValues)
    having("input[type=checkbox]").forEach(labelCheckbox)
    new Set(having(".bk-tab").map((tab) => tab.parentElement)).forEach(markTabs)
    unlist()
  }

  // A tab's content may arrive from the server after it is chosen: name its sliders then.
  const annotateSoon = () => [300, 1500, 5000].forEach((ms) => setTimeout(annotate, ms))

  // Choosing a tab may rebuild the whole tab view (the Mechanisms tab is built when first
  // opened), and the focus falls back to the page: it goes to the new header of the chosen tab,
  // found by its title. Watched for 10 s; a focus the user has moved elsewhere is left alone.
  const keepFocus = (title, tries = 200) => {
    const lost = document.activeElement == null || document.activeElement === document.body
    if (lost) {
      const tabs = everywhere(document, ".bk-tab.bk-active")
      const chosen = tabs.find((tab) => tab.textContent === title)
      if (chosen != null) chosen.focus()
    }
    if (tries > 0) setTimeout(() => keepFocus(title, tries - 1), 50)
  }

  const KEYS = {
    Enter: (i) => i,
    " ": (i) => i,
    ArrowRight: (i, n) => (i + 1) % n,
    ArrowLeft: (i, n) => (i - 1 + n) % n,
    Home: () => 0,
    End: (_i, n) => n - 1,
  }

  document.addEventListener(
    "keydown",
    (event) => {
      const tab = event.composedPath()[0]
      const move = KEYS[event.key]
      if (move == null || !(tab instanceof HTMLElement) || !tab.classList.contains("bk-tab")) return
      event.preventDefault()
      const tabs = [...tab.parentElement.children]
      const index = move(tabs.indexOf(tab), tabs.length)
      tabs[index].focus()
      tabs[index].click()
      keepFocus(tabs[index].textContent)
    },
    true,
  )

  document.addEventListener(
    "click",
    (event) => {
      const target = event.composedPath()[0]
      if (target instanceof HTMLElement && target.classList.contains("bk-tab")) annotateSoon()
      // a card's sliders are built when it first opens
      else if (event.composedPath().some((el) => el.classList?.contains("card-header"))) annotateSoon()
    },
    true,
  )

  document.addEventListener(
    "focusin",
    (event) => {
      const target = event.composedPath()[0]
      if (!(target instanceof HTMLElement)) return
      if (target.classList.contains("noUi-handle")) nameHandle(target)
      if (target.classList.contains("bk-tab")) markTabs(target.parentElement)
    },
    true,
  )

  // Whatever the server changes (a tab's content, a card's sliders, a view built when first
  // seen) is drawn a moment later: annotated then, once the changes pause.
  // (A run's data, sent or drawn by the player 30 times a second, adds no widget.)
  let pending = null
  const afterChanges = (event) => {
    if (event.model?.constructor?.__name__ === "ColumnDataSource") return
    clearTimeout(pending)
    pending = setTimeout(annotateSoon, 100)
  }
  for (const doc of window.Bokeh.documents) doc.on_change(afterChanges)

  annotate()
}
