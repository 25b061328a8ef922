// Typesets the LaTeX that pymdownx.arithmatex (generic mode) leaves in the pages:
// inline \( ... \) in span.arithmatex, display \[ ... \] in div.arithmatex.
// KaTeX 0.16.11 is vendored beside this file (javascripts/katex/, MIT licence), so the
// site renders its formulas without a network; where a script is blocked, the raw
// LaTeX stays readable.
document.addEventListener("DOMContentLoaded", function () {
  document.querySelectorAll(".arithmatex").forEach(function (el) {
    var tex = (el.textContent || "").trim();
    var display = tex.startsWith("\\[") && tex.endsWith("\\]");
    if (display || (tex.startsWith("\\(") && tex.endsWith("\\)"))) {
      tex = tex.slice(2, -2);
    }
    katex.render(tex, el, { displayMode: display, throwOnError: false });
  });
});
