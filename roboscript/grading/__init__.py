"""Grading: teacher test specs run against students' missions on the simulator.

* :mod:`~roboscript.grading.spec` reads a test spec (world, robot, run variants, expectations);
* :mod:`~roboscript.grading.expectations` judges each expectation on a run's record, with a
  signed margin and the time of the first violation;
* :mod:`~roboscript.grading.run` is one graded run, a pure function of spec, mission and
  variant; :mod:`~roboscript.grading.pool` runs many, each in a worker process of its own with
  a wall-clock limit;
* :mod:`~roboscript.grading.batch` finds the submissions and grades a class;
* the reports: :mod:`~roboscript.grading.table` (terminal), :mod:`~roboscript.grading.junit`,
  :mod:`~roboscript.grading.gradebook` (CSV), :mod:`~roboscript.grading.html_report` (the
  teacher's pages and one per student), :mod:`~roboscript.grading.json_report`,
  :mod:`~roboscript.grading.gradescope` (Gradescope's ``results.json``),
  :mod:`~roboscript.grading.prairielearn` (PrairieLearn's); every one of them caps and cleans
  student-controlled text, and words hidden runs for students, through
  :mod:`~roboscript.grading.text`;
* :mod:`~roboscript.grading.shards` grades a class in parts (``--shard``) and merges their
  results files (``roboscript gradebook``);
* :mod:`~roboscript.grading.autograder` packages the specs for Gradescope, GitHub Classroom and
  PrairieLearn, with the wheels :mod:`~roboscript.grading.wheels` makes offline.
"""
