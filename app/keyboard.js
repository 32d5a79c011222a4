// Keyboard and screen readers, where Bokeh 3.9's widgets fall short: tab headers are focusable
// but do not react to keys and carry no role; slider handles have no accessible name. Listens on
// the document (events from the widgets' shadow DOM reach it), so widgets drawn later (the
// Mechanisms tab) are covered too. Runs once a page, on Bokeh's document_ready.
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
  const nameHandle = (handle) => {
    const title = handle.getRootNode().querySelector(".bk-slider-title")
    if (title == null) return
    const first = title.firstChild
    const text = first != null && first.nodeType === Node.TEXT_NODE ? first.textContent : title.textContent
    const label = text.replace(/:\s*$/, "").trim()
    if (label) handle.setAttribute("aria-label", label)
  }

  const markTabs = (list) => {
    list.setAttribute("role", "tablist")
    for (const tab of list.children) {
      tab.setAttribute("role", "tab")
      tab.setAttribute("aria-selected", String(tab.classList.contains("bk-active")))
    }
  }

  const annotate = () => {
    everywhere(document, ".noUi-handle").forEach(nameHandle)
    new Set(everywhere(document, ".bk-tab").map((tab) => tab.parentElement)).forEach(markTabs)
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

  annotate()
}
