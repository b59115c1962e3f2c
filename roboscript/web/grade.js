/* roboscript in a browser tab: the practice grade. A test spec the teacher shipped in the page
 * (roboscript web build --spec) or one the student opens is graded against the mission in the
 * editor by roboscript's own grading code (roboscript.grading.practice), in this page: every
 * run, each expectation held or not, the score and points, and each visible run's replay.
 * Starts when app.js says Python is ready (the "roboscript-ready" event).
 */
(function () {
  "use strict";

  function $(role) { return document.querySelector("[data-role='" + role + "']"); }
  function button(action) { return document.querySelector("[data-action='" + action + "']"); }
  function element(tag, text, className) {
    var made = document.createElement(tag);
    if (text !== undefined) made.textContent = text;
    if (className) made.className = className;
    return made;
  }
  function plural(count, word) { return count + " " + word + (count === 1 ? "" : "s"); }
  function points(value) { return String(Math.round(value * 100) / 100); }

  var app = null, specs = { shipped: [], opened: [] }, lastRuns = [];
  var sent = { shipped: null, opened: null };  // each slot's files, for a fresh worker

  function load(files, slot) {
    sent[slot] = files;
    return app.call("bridge", "load_specs", JSON.stringify(files), slot).then(function (text) {
      loaded(JSON.parse(text), slot);
    }, function (failure) { app.say(app.notAnswered(failure)); });
  }

  function loaded(answer, slot) {
    specs[slot] = answer.specs;
    var problems = $("spec-problems");
    problems.textContent = "";
    answer.problems.forEach(function (p) {
      problems.appendChild(element("li", p.text, "rs-" + p.severity));
    });
    if (slot === "opened" && !answer.specs.length && !answer.problems.length) {
      problems.appendChild(element("li", "None of these files is a test spec (a test spec " +
        "starts with 'test:'): open the spec your teacher gave you, with its world and check " +
        "files if it has any.", "rs-error"));
    }
    fill(slot === "opened" && answer.specs.length ? answer.specs[0].path : null);
  }

  function fill(choose) {
    var select = $("spec"), keep = choose || select.value;
    select.textContent = "";
    var all = specs.shipped.concat(specs.opened);
    if (!all.length) select.appendChild(element("option", "— open a test spec —"));
    all.forEach(function (spec) {
      var option = element("option", spec.test);
      option.value = spec.path;
      select.appendChild(option);
    });
    if (keep && all.some(function (s) { return s.path === keep; })) select.value = keep;
    about();
  }

  function chosen() {
    var path = $("spec").value;
    return specs.shipped.concat(specs.opened).filter(function (s) { return s.path === path; })[0];
  }

  function about() {
    var spec = chosen();
    button("grade").disabled = !spec;
    $("spec-about").textContent = spec ?
      spec.test + ": " + spec.description.trim() + " Runs on " + spec.robot + ", " +
      plural(spec.runs.length, "run") + " (" + spec.runs.map(function (r) {
        return r.label;
      }).join("; ") + "), worth " + plural(spec.points, "point") + "; checks: " +
      spec.expect.map(function (e) {
        return e.name + (e.required ? " (required)" : "");
      }).join(", ") + "." : "";
  }

  function openedSpecs() {
    var input = $("spec-file");
    var files = Array.prototype.slice.call(input.files || []);
    if (!files.length) return;
    Promise.all(files.map(function (file) { return file.text(); })).then(function (texts) {
      var named = {};
      files.forEach(function (file, i) { named[file.name] = texts[i]; });
      load(named, "opened");
      input.value = "";
    });
  }

  function replay(index) {
    var run = lastRuns[index], box = $("viewer");
    if (!run || !run.viewer) return;
    box.textContent = "";
    box.innerHTML = run.viewer;  // roboscript's own block: the run as JSON in a script
    window.roboscriptViewer.mount(box.querySelector(".rs-viewer"));
    box.setAttribute("data-showing", "grade run " + (index + 1));
  }

  function showGrade(answer) {
    var out = $("grade");
    out.textContent = "";
    lastRuns = [];
    if (!answer.grade) {
      answer.problems.forEach(function (p) { out.appendChild(element("p", p.text, "rs-error")); });
      return;
    }
    var g = answer.grade;
    lastRuns = g.runs;
    var total = element("p", (g.passed ? "✓ " : "✗ ") + answer.spec.test + ": " +
      points(g.points) + " of " + plural(g.max_points, "point") + ", " + g.passed_runs +
      " of " + plural(g.total_runs, "run") + " passed", "rs-grade-total");
    total.setAttribute("data-role", "grade-total");
    total.setAttribute("data-points", String(g.points));
    total.setAttribute("data-max-points", String(g.max_points));
    total.setAttribute("data-passed", g.passed ? "1" : "0");
    out.appendChild(total);
    var list = element("ol", undefined, "rs-runs");
    g.runs.forEach(function (run, i) {
      var item = element("li", undefined, run.passed ? "rs-pass" : "rs-fail");
      item.setAttribute("data-run", String(i));
      item.setAttribute("data-status", run.status);
      item.setAttribute("data-score", String(run.score));
      item.setAttribute("data-points", String(run.points));
      item.appendChild(element("strong", run.label));
      item.appendChild(document.createTextNode(": " + run.status + ", " + points(run.points) +
        " of " + plural(run.max_points, "point") + (run.message ? " — " + run.message : "")));
      if (run.advice) item.appendChild(element("p", run.advice, "rs-note"));
      var checks = element("ul", undefined, "rs-verdicts");
      run.verdicts.forEach(function (v) {
        var line = element("li", (v.passed ? "✓ " : "✗ ") + (v.text || v.name + " " +
          (v.passed ? "passed" : "failed")) + (v.required ? " (required)" : ""));
        line.setAttribute("data-name", v.name);
        line.setAttribute("data-passed", v.passed ? "1" : "0");
        checks.appendChild(line);
      });
      item.appendChild(checks);
      if (run.hidden) {
        item.appendChild(element("p", "A hidden run: its start and seed are not shown here, " +
          "so make the mission work from any start.", "rs-note"));
      } else if (run.viewer) {
        var show = element("button", "Show this run's replay");
        show.type = "button";
        show.setAttribute("data-action", "grade-replay");
        show.addEventListener("click", function () { replay(i); });
        item.appendChild(show);
      }
      list.appendChild(item);
    });
    out.appendChild(list);
    var first = g.runs.findIndex(function (r) { return r.viewer && !r.passed; });
    replay(first >= 0 ? first : g.runs.findIndex(function (r) { return r.viewer; }));
  }

  function grade() {
    var spec = chosen();
    if (!spec) return;
    button("grade").disabled = true;
    app.busy(1);
    app.say("Grading against " + spec.test + " (" + plural(spec.runs.length, "run") +
            ")… (■ Stop ends it)");
    app.call("bridge", "grade_text", app.name(), app.text(), spec.path).then(function (text) {
      var answer = JSON.parse(text);
      showGrade(answer);
      app.say(answer.grade ? "Graded: " + points(answer.grade.points) + " of " +
        plural(answer.grade.max_points, "point") : "The test spec has errors");
      document.body.setAttribute("data-graded", String(Date.now()));
    }, function (failure) {
      var out = $("grade");
      out.textContent = "";
      out.appendChild(element("p", app.notAnswered(failure), "rs-error"));
      document.body.setAttribute("data-graded", String(Date.now()));
    }).then(function () {
      app.busy(-1);
      button("grade").disabled = !chosen();
    });
  }

  document.addEventListener("roboscript-ready", function (event) {
    app = event.detail;
    $("spec").addEventListener("change", about);
    button("open-spec").addEventListener("click", function () { $("spec-file").click(); });
    $("spec-file").addEventListener("change", openedSpecs);
    button("open-spec").disabled = false;
    button("grade").addEventListener("click", grade);
    var shipped = window.rsSpecs || {};
    if (Object.keys(shipped).length) app.pending.push(load(shipped, "shipped"));
    else fill(null);
  });

  // Python started again (after Stop): its fresh worker is given the specs again
  document.addEventListener("roboscript-restarted", function () {
    ["shipped", "opened"].forEach(function (slot) { if (sent[slot]) load(sent[slot], slot); });
  });
})();
