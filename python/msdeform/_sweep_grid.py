"""A sweep description (JSON) and its task grid, for msdeform.sweep.

A sweep file names scenario files, methods, seeds, named variants (sets of options) and option
axes; the task grid is their product, expanded in a fixed order, and every task has a stable id:
the first 12 hex digits of the SHA-256 of its parameters as canonical JSON (sorted keys, no
spaces). docs/decisions/sweeps.md records the schema and the choices.

    {"scenarios": ["../scenarios/cactus.json"],          # relative to the sweep file
     "methods": ["multiscale", "static"],                 # default ["multiscale"]
     "seeds": [1, 2, 3],                                  # default [the --seed default]
     "variants": {"default": {}, "paper": {"rigidity": "paper"}},
     "options": {"w_con": [100, 1000], "solver": ["gauss_newton", "ceres"]}}

Option names are msdeform's command-line flag names (msdeform.option_flags()); a name with a dot,
or a DeformerOptions field without a flag, sets that field of the options the flags built
("selection.member_extent": "mean"). A method's own option is named as the options table names it
("fastlsm.steps_per_frame", "cgal.iterations"; msdeform.option_rows()) and applies to the methods
that read it; the other methods' tasks leave it out (and are not repeated along its axis).
"""

import hashlib
import itertools
import json
import math
import os
import posixpath

import msdeform

# Methods a task can run: the Deformer's three and CGAL's ARAP (experiments/runner.h).
# Every registered method (methods/registry.h); the graph methods take the Deformer option
# grid, the others (CGAL's ARAP and SR-ARAP, FastLSM) the grid of their own options
# (method_rows()), once per scenario without any (cgal_iterations for CGAL's).
METHODS = tuple(msdeform.METHODS)
DEFORMER_METHODS = tuple(msdeform.GRAPH_METHODS)  # the registry's descriptors

# Which option the seeds axis sets: the --seed flag (graph and rigidity seeds, as the command
# line), or one of the two seeds alone (no flag has them; set as DeformerOptions fields).
SEED_FIELDS = ("seed", "rigidity.seed", "graph.seed")

# Keys of a sweep file; any other key is an error.
SWEEP_KEYS = ("description", "scenarios", "methods", "seeds", "seed_field", "variants",
              "options", "frames", "arap_reference", "time_other_backend", "cgal_iterations",
              "tables", "chart", "summary_metrics")

# Prefix of the result columns that hold a task's option values (a flag named like a metric,
# e.g. cell_width, would otherwise share its column).
OPTION_COLUMN_PREFIX = "opt_"


class SweepError(ValueError):
    """Bad input in a sweep description: the message names the file and the field."""


def task_id(params):
    """The stable id of a task: 12 hex digits of the SHA-256 of canonical_json(params)."""
    return hashlib.sha256(canonical_json(params).encode("utf-8")).hexdigest()[:12]


def canonical_json(value):
    """JSON with sorted keys and no spaces: the text a task id is the hash of."""
    return json.dumps(value, sort_keys=True, separators=(",", ":"), ensure_ascii=False,
                      allow_nan=False)


def method_rows():
    """{row name: row} of the methods' own options ("fastlsm.steps_per_frame"), each row a dict
    of msdeform.option_rows() (type, default, keywords, methods: those that read it)."""
    return {row["name"]: row for row in msdeform.option_rows() if row["methods"]}


def applies(name, method, rows=None):
    """True when option `name` is one that `method` reads: a method's own row for the methods
    that read it, any other option for the graph methods."""
    rows = rows if rows is not None else method_rows()
    if name in rows:
        return method in rows[name]["methods"]
    return method in DEFORMER_METHODS


def method_keywords(settings):
    """The Method / run_method keywords of a task's own options ("fastlsm.steps_per_frame" ->
    fastlsm_steps_per_frame)."""
    return {name.replace(".", "_"): value for name, value in settings.items()}


def flag_types():
    """{flag name: gflags type name} of the Deformer's command-line flags."""
    return {flag["name"]: flag["type"] for flag in msdeform.option_flags()}


def _typed_default(flag):
    """A flag's default (option_flags() gives text) as the Python value of its type."""
    text, kind = flag["default"], flag["type"]
    if kind == "bool":
        return text == "true"
    if kind in ("int32", "int64", "uint32", "uint64"):
        return int(text)
    if kind == "double":
        return float(text)
    return text


def option_default(name):
    """The value a task has for an option it does not set: the flag's default, the field's
    value in a default DeformerOptions (with the default flags), or a method row's default."""
    row = method_rows().get(name)
    if row is not None:
        return {"int": int, "double": float}.get(row["type"], str)(row["default"])
    for flag in msdeform.option_flags():
        if flag["name"] == name:
            return _typed_default(flag)
    value = msdeform.options_from_flags({})
    for part in name.split("."):
        value = getattr(value, part)
    return value


def is_field_path(name, flags):
    """True when an option name sets a DeformerOptions field rather than a flag."""
    return name not in flags and ("." in name or name in msdeform.DeformerOptions.fields)


def set_field(options, path, value):
    """Sets options.<path> (dotted, e.g. "selection.member_extent") to value.

    Raises ValueError naming the path for a name that is not a field, and passes on the
    setter's TypeError/ValueError (it names the field and what it expects).
    """
    parts = path.split(".")
    target = options
    for depth, part in enumerate(parts):
        fields = getattr(type(target), "fields", ())
        if part not in fields:
            owner = ".".join(["DeformerOptions"] + parts[:depth])
            raise ValueError(f"{part} is not a field of {owner} (fields: {', '.join(fields)})")
        if depth + 1 < len(parts):
            target = getattr(target, part)
    setattr(target, parts[-1], value)


def build_options(method, settings, seed, seed_field, flags=None):
    """The DeformerOptions of one task: the command line's options from the flags among
    `settings` (threads 1, as the experiment runner, unless set), the method and the seed,
    then the field paths among `settings` set on them, then checked.

    Raises ValueError or TypeError with the message of the flag code or the field setter.
    """
    flags = flags if flags is not None else flag_types()
    flag_values = {"threads": 1, "method": method}
    fields = {}
    for name, value in settings.items():
        if is_field_path(name, flags):
            fields[name] = value
        else:
            flag_values[name] = value
    if seed_field == "seed":
        flag_values["seed"] = seed
    else:
        fields[seed_field] = seed
    options = msdeform.options_from_flags(flag_values)
    for path, value in fields.items():
        set_field(options, path, value)
    options.check()
    return options


class Sweep:
    """A loaded sweep description and its task grid.

    file: the sweep file as given; folder: its folder (scenario paths are relative to it);
    settings: the sweep-level keys (frames, arap_reference, time_other_backend,
    cgal_iterations, seed_field); option_names: every option a task can set, in column order;
    tasks: the grid in order, each a dict with id, index (1-based), params (what the id hashes),
    scenario_path (absolute) and columns (the row's parameter columns);
    tables, chart, summary_metrics: what to write besides results.csv.
    """

    def __init__(self, file, raw):
        """Checks `raw` (the parsed JSON of `file`) and expands its grid; raises SweepError."""
        self.file = file
        self.folder = os.path.dirname(os.path.abspath(file))
        self._flags = flag_types()
        if not isinstance(raw, dict):
            self._fail("", "expected a JSON object")
        for key in raw:
            if key not in SWEEP_KEYS:
                self._fail(key, f"unknown key (the keys are {', '.join(SWEEP_KEYS)})")
        self.description = self._string(raw, "description", "")
        self.scenarios = self._scenarios(raw)
        self.methods = self._methods(raw)
        self.seed_field = raw.get("seed_field", "seed")
        if self.seed_field not in SEED_FIELDS:
            self._fail("seed_field",
                       f"{self.seed_field!r}: expected one of {', '.join(SEED_FIELDS)}")
        self.seeds = self._seeds(raw)
        self.variants = self._variants(raw)
        self.options = self._options(raw)
        self.settings = {
            "frames": self._integer(raw, "frames", 0, 0, msdeform.MAX_SCENARIO_FRAMES),
            "arap_reference": self._bool(raw, "arap_reference", False),
            "time_other_backend": self._bool(raw, "time_other_backend", False),
            "cgal_iterations": self._integer(raw, "cgal_iterations", None, 1),
            "seed_field": self.seed_field,
        }
        self.option_names = list(self.options)
        for settings in self.variants.values():
            for name in settings:
                if name not in self.option_names:
                    self.option_names.append(name)
        self.tables = self._tables(raw)
        self.chart = self._chart(raw)
        self.summary_metrics = self._string_list(raw, "summary_metrics", None)
        self.tasks = self._expand()

    # -- checks of the description's fields ------------------------------------------------

    def _fail(self, field, message):
        """Raises SweepError "<file>: <field>: <message>"."""
        where = f"{self.file}: {field}: " if field else f"{self.file}: "
        raise SweepError(where + message)

    def _string(self, raw, key, default):
        """raw[key] as a str (default when absent)."""
        value = raw.get(key, default)
        if not isinstance(value, str):
            self._fail(key, f"expected a string, got {json.dumps(value)}")
        return value

    def _bool(self, raw, key, default):
        """raw[key] as a bool (default when absent)."""
        value = raw.get(key, default)
        if not isinstance(value, bool):
            self._fail(key, f"expected true or false, got {json.dumps(value)}")
        return value

    def _integer(self, raw, key, default, minimum, maximum=None):
        """raw[key] as an int in minimum..maximum (default when absent)."""
        if key not in raw:
            return default
        value = raw[key]
        if (isinstance(value, bool) or not isinstance(value, int) or value < minimum
                or (maximum is not None and value > maximum)):
            expected = f">= {minimum}" if maximum is None else f"in {minimum}..{maximum}"
            self._fail(key, f"expected an integer {expected}, got {json.dumps(value)}")
        return value

    def _list(self, raw, key, default):
        """raw[key] as a non-empty list (default when absent)."""
        if key not in raw:
            return default
        value = raw[key]
        if not isinstance(value, list) or not value:
            self._fail(key, f"expected a non-empty list, got {json.dumps(value)}")
        return value

    def _string_list(self, raw, key, default):
        """raw[key] as a non-empty list of strings (default when absent)."""
        values = self._list(raw, key, default)
        if values is default:
            return default
        for i, value in enumerate(values):
            if not isinstance(value, str) or not value:
                self._fail(f"{key}[{i}]", f"expected a non-empty string, got {json.dumps(value)}")
        return values

    def _scenarios(self, raw):
        """The scenario entries: (path as written, normalised; absolute path), each a file."""
        if "scenarios" not in raw:
            self._fail("scenarios",
                       "missing (a list of scenario files, relative to the sweep file)")
        scenarios = []
        for i, path in enumerate(self._string_list(raw, "scenarios", None)):
            written = posixpath.normpath(path.replace(os.sep, "/"))
            absolute = os.path.normpath(os.path.join(self.folder, path))
            if not os.path.isfile(absolute):
                self._fail(f"scenarios[{i}]", f"{path}: no such file ({absolute})")
            scenarios.append((written, absolute))
        return scenarios

    def _methods(self, raw):
        """The methods, each one of METHODS."""
        methods = self._string_list(raw, "methods", ["multiscale"])
        for i, method in enumerate(methods):
            if method not in METHODS:
                self._fail(f"methods[{i}]", f"{method!r}: expected one of {', '.join(METHODS)}")
        return methods

    def _seeds(self, raw):
        """The seeds, integers >= 0 (default: the --seed flag's default alone)."""
        seeds = self._list(raw, "seeds", None)
        if seeds is None:
            return [option_default("seed")]
        for i, seed in enumerate(seeds):
            if isinstance(seed, bool) or not isinstance(seed, int) or not 0 <= seed < 2**64:
                self._fail(f"seeds[{i}]",
                           f"expected an integer in 0..2^64-1, got {json.dumps(seed)}")
        return seeds

    def _check_name(self, field, name):
        """An option name: a flag, or a field path; not method or a seed (their own axes)."""
        if name == "method":
            self._fail(field, "the method is the 'methods' axis, not an option")
        if name in SEED_FIELDS:
            self._fail(field, "the seed is the 'seeds' axis (and 'seed_field'), not an option")
        if name in method_rows():
            return
        if name not in self._flags and not is_field_path(name, self._flags):
            try:
                msdeform.options_from_flags({name: True})
            except (TypeError, ValueError) as error:
                self._fail(field, str(error))
            self._fail(field, f"{name}: not an option flag or DeformerOptions field")

    def _check_value(self, field, name, value):
        """One option value, checked by building the options with it (the flag code's or the
        field setter's message)."""
        if not isinstance(value, (bool, int, float, str)):
            self._fail(field, f"expected a bool, number or string, got {json.dumps(value)}")
        if isinstance(value, float) and not math.isfinite(value):
            self._fail(field, f"expected a finite number, got {value}")
        if name in method_rows():
            try:  # the row's own parse and range, as Method checks them
                msdeform.describe_method_options(**method_keywords({name: value}))
            except (TypeError, ValueError) as error:
                self._fail(field, str(error))
            return
        # The value alone, under the energy that reads it (an arap.* option is refused under
        # another, which the whole task's options decide).
        settings = {name: value}
        if name.startswith("arap.") or name.startswith("arap_"):
            settings["energy"] = "arap"
        try:
            build_options("multiscale", settings, option_default("seed"), "seed", self._flags)
        except (TypeError, ValueError) as error:
            self._fail(field, str(error))

    def _variants(self, raw):
        """{name: {option: value}} in file order (default {"default": {}})."""
        variants = raw.get("variants", {"default": {}})
        if not isinstance(variants, dict) or not variants:
            self._fail("variants", "expected a non-empty object {name: {option: value}}")
        for name, settings in variants.items():
            if not name or not isinstance(settings, dict):
                self._fail(f"variants.{name}", "expected an object {option: value}")
            for option, value in settings.items():
                field = f"variants.{name}.{option}"
                self._check_name(field, option)
                self._check_value(field, option, value)
        return variants

    def _options(self, raw):
        """{option: [values]} in file order: the option axes."""
        options = raw.get("options", {})
        if not isinstance(options, dict):
            self._fail("options", "expected an object {option: [values]}")
        for option, values in options.items():
            self._check_name(f"options.{option}", option)
            if not isinstance(values, list) or not values:
                self._fail(f"options.{option}",
                           f"expected a non-empty list of values, got {json.dumps(values)}")
            for i, value in enumerate(values):
                self._check_value(f"options.{option}[{i}]", option, value)
            for variant, settings in self.variants.items():
                if option in settings:
                    self._fail(f"options.{option}",
                               f"variant {variant!r} sets it too; set it in one place")
        return options

    def _tables(self, raw):
        """The table projections: [{name, columns, methods, energies}] (methods None: every
        method; energies None: every energy, the rows' energy column)."""
        tables = self._list(raw, "tables", [])
        checked = []
        for i, table in enumerate(tables):
            field = f"tables[{i}]"
            if not isinstance(table, dict) or set(table) - {"name", "columns", "methods",
                                                            "energies"}:
                self._fail(field, 'expected {"name": ..., "columns": [...], "methods": [...], '
                                  '"energies": [...]}')
            name = self._string(table, "name", "")
            if not name or "/" in name or name in ("results", "summary", "tasks"):
                self._fail(field + ".name",
                           f"{name!r}: expected a file stem other than results, summary, tasks")
            columns = self._string_list(table, "columns", None)
            if columns is None:
                self._fail(field + ".columns", "missing")
            methods = self._string_list(table, "methods", None)
            energies = self._string_list(table, "energies", None)
            checked.append({"name": name, "columns": columns, "methods": methods,
                            "energies": energies})
        return checked

    def _chart(self, raw):
        """The chart: {"x": parameter, "y": metric} (None: chosen from the grid)."""
        chart = raw.get("chart", {})
        if not isinstance(chart, dict) or set(chart) - {"x", "y"}:
            self._fail("chart", "expected {\"x\": parameter, \"y\": metric}")
        return {"x": chart.get("x"), "y": chart.get("y")}

    # -- the grid --------------------------------------------------------------------------

    def _expand(self):
        """The task grid: scenarios x methods x variants x option axes x seeds, in that order
        (seeds innermost); a method without Deformer options (cgal_arap, cgal_sr_arap,
        fastlsm) once per scenario."""
        axes = [[(name, value) for value in values] for name, values in self.options.items()]
        points = [dict(point) for point in itertools.product(*axes)]
        defaults = {name: option_default(name) for name in self.option_names}
        rows = method_rows()
        tasks, seen = [], {}
        for written, absolute in self.scenarios:
            for method in self.methods:
                # The options a method does not read are left out of its tasks; a grid point
                # that differs only in those is the same task.
                def own(settings):
                    return {k: v for k, v in settings.items() if applies(k, method, rows)}
                if method not in DEFORMER_METHODS:
                    grid = []
                    for variant in self.variants:
                        for point in points:
                            settings = own({**self.variants[variant], **point})
                            if (None, settings, None) not in grid:
                                grid.append((None, settings, None))
                else:
                    grid = []
                    for variant in self.variants:
                        for point in points:
                            for seed in self.seeds:
                                if (variant, own(point), seed) not in grid:
                                    grid.append((variant, own(point), seed))
                for variant, point, seed in grid:
                    task = self._task(written, absolute, method, variant, point, seed, defaults)
                    if task["id"] in seen:
                        self._fail("", f"tasks {seen[task['id']]} and {len(tasks) + 1} have the "
                                       f"same parameters ({describe_task(task)}): a scenario, "
                                       f"method, variant, seed or value listed twice")
                    task["index"] = len(tasks) + 1
                    seen[task["id"]] = task["index"]
                    tasks.append(task)
        for task in tasks:
            if task["method"] in DEFORMER_METHODS:
                try:
                    build_options(task["method"], task["params"]["options"], task["params"]["seed"],
                                  self.seed_field, self._flags)
                except (TypeError, ValueError) as error:
                    self._fail("", f"task {task['index']} ({describe_task(task)}): {error}")
        return tasks

    def _task(self, written, absolute, method, variant, point, seed, defaults):
        """One task: its params (hashed into the id), paths and parameter columns."""
        frames = self.settings["frames"]
        cgal_iterations = self.settings["cgal_iterations"]
        if method not in DEFORMER_METHODS:
            params = {"scenario": written, "method": method, "frames": frames,
                      "cgal_iterations": cgal_iterations}
            values = {}
            if point:  # its own options (without any, the id is as before they existed)
                params["options"] = point
                values = {name: point.get(name, defaults[name]) for name in self.option_names
                          if applies(name, method)}
        else:
            settings = {k: v for k, v in self.variants[variant].items() if applies(k, method)}
            settings.update(point)
            params = {"scenario": written, "method": method, "variant": variant, "seed": seed,
                      "seed_field": self.seed_field, "options": settings, "frames": frames,
                      "arap_reference": self.settings["arap_reference"],
                      "time_other_backend": self.settings["time_other_backend"],
                      "cgal_iterations": cgal_iterations}
            values = {name: settings.get(name, defaults[name]) for name in self.option_names
                      if applies(name, method)}
        columns = {"scenario_file": written, "method": method, "variant": variant,
                   "seed": seed, "frames": frames}
        for name in self.option_names:
            columns[OPTION_COLUMN_PREFIX + name] = values.get(name)
        label = [posixpath.splitext(posixpath.basename(written))[0], method]
        if method in DEFORMER_METHODS:
            label.append(variant)
            label += [f"{name}={json.dumps(value)}" for name, value in point.items()]
            label.append(f"seed {seed}")
        else:
            label += [f"{name}={json.dumps(value)}" for name, value in (point or {}).items()]
        return {"id": task_id(params), "method": method, "params": params,
                "scenario_path": absolute, "columns": columns, "label": " / ".join(label)}


def describe_task(task):
    """A short label: scenario / method / variant / the option axes' values / seed."""
    return task["label"]


def load_sweep(path):
    """Reads and checks a sweep file and expands its grid; raises SweepError naming the file
    and the field on bad input."""
    try:
        with open(path, encoding="utf-8") as file:
            text = file.read()
    except OSError as error:
        raise SweepError(f"{path}: {error.strerror}") from None
    try:
        raw = json.loads(text)
    except json.JSONDecodeError as error:
        raise SweepError(f"{path}: line {error.lineno} column {error.colno}: {error.msg}") from None
    return Sweep(path, raw)
