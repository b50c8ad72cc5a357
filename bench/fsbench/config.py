"""The harness's settings: the repository root, the method registry (METHODS and the Method tuple, the irradiance
cache's bench arguments, arguments of unregistered integrators), per-scene reference defaults, the goals, the
metrics, the CSV columns and header, and the parsing of method names and --method-args (method_spec, spec_of).
"""
import collections
import os
import shlex
import sys


# The repository root: this file is bench/fsbench/config.py.
REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

# A named method: the integrator, its extra renderer arguments, whether it renders with a first-shot table
# (then firstshot-preprocess runs first and its time counts), and whether it is one of the baselines a user
# would pick (path tracing without first-shot; the speed comparisons use the best of them).
Method = collections.namedtuple("Method", "integrator args firstshot baseline about")

# The irradiance cache's defaults (512 samples, 3 bounces) fill ~2*10^5 records on cornell at 160x120, a minute
# on 2 cores; the bench uses a cheaper cache. No --ambient: past the last cached bounce the integrator continues
# the path (an --ambient 0 would truncate the light). The CSV shows exactly what ran.
IC_ARGS = ["--ic-samples", "128", "--bounces", "2", "--one-pass"]  # as measured for the README (the faster mode)

METHODS = {
    "path": Method("path", ["--light-sampler", "all"], False, True,
                   "path tracing, next-event estimation to every light"),
    "path-tree": Method("path", ["--light-sampler", "tree"], False, True,
                        "path tracing, a light tree picks one light per vertex"),
    "path+firstshot": Method("path", ["--light-sampler", "all", "--patch-nee", "off"], True, False,
                             "path tracing with first-shot; shadow rays to every small light at camera-visible "
                             "surfaces, lit patches met by BSDF sampling"),
    "path+firstshot-tree": Method("path", ["--light-sampler", "tree", "--patch-nee", "off"], True, False,
                                  "path tracing with first-shot (the renderer's defaults); a light tree picks the "
                                  "small light at camera-visible surfaces"),
    "path+firstshot-patchnee": Method("path", ["--light-sampler", "all", "--patch-nee", "every"], True, False,
                                      "path tracing with first-shot; lit patches sampled as lights at every vertex"),
    "irradiance-cache": Method("irradiance-cache", ["--light-sampler", "tree"] + IC_ARGS, False, False,
                               "irradiance cache, no first-shot (not a baseline: shown for comparison)"),
    "irradiance-cache+firstshot": Method("irradiance-cache", ["--light-sampler", "all"] + IC_ARGS, True, False,
                                         "irradiance cache with first-shot"),
    "light": Method("light", [], False, False,
                    "light tracing (shooting, docs/light-tracing.md; not a baseline: shown for comparison)"),
    "bdpt": Method("bdpt", [], False, False,
                   "bidirectional path tracing, MIS over all strategies (docs/bdpt.md; not a baseline: shown for "
                   "comparison)"),
    "light+firstshot": Method("light", ["--shoot-firstshot", "patches"], True, False,
                              "light tracing with first-shot: particles leave the lit patches, the small lights' "
                              "direct light at camera-visible surfaces by shadow rays (docs/light-tracing.md)"),
    "bdpt+firstshot": Method("bdpt", ["--shoot-firstshot", "patches"], True, False,
                             "bidirectional path tracing with first-shot: light subpaths leave the lit patches "
                             "(docs/bdpt.md)"),
    "bundle": Method("bundle", [], False, False,
                     "ray-bundle stochastic iteration, no first-shot: small lights emit through the bundle, NEE at "
                     "camera-visible surfaces (not a baseline: the paper's plain method, docs/bundle.md)"),
    "bundle+firstshot": Method("bundle", [], True, False,
                               "ray-bundle stochastic iteration with incoming first-shot (the paper's §5)"),
}
DEFAULT_METHODS = list(METHODS)

# Arguments of an integrator used by a method name that is not in METHODS (NAME or NAME+firstshot).
DEFAULT_METHOD_ARGS = {
    "irradiance-cache": IC_ARGS,
}

FIRSTSHOT_SUFFIX = "+firstshot"

# Per scene: the reference's starting spp (it doubles from there until converged) and its method.
# office-floor: NEE to every one of its >= 200 lights costs hundreds of shadow rays per vertex; the light tree
# is unbiased too.
SCENE_DEFAULTS = {
    "cornell": {"ref_spp": 1024, "ref_method": "path"},
    "many-lights": {"ref_spp": 256, "ref_method": "path"},
    "sierpinski-glossy": {"ref_spp": 512, "ref_method": "path"},
    "fixture-room": {"ref_spp": 256, "ref_method": "path"},
    "office-floor": {"ref_spp": 128, "ref_method": "path-tree"},
    "ward-sphere": {"ref_spp": 512, "ref_method": "path"},
}
FALLBACK_DEFAULTS = {"ref_spp": 256, "ref_method": "path"}

# The requirement: the ratio best baseline time / best first-shot time must be at least min_ratio, at the
# smallest target ("smallest") or at every target ("every"), rel. RMSE.
GOALS = {
    "cornell": {"min_ratio": 1.0, "at": "every"},
    "many-lights": {"min_ratio": 10.0, "at": "smallest"},
    "fixture-room": {"min_ratio": 10.0, "at": "smallest"},
    "office-floor": {"min_ratio": 10.0, "at": "smallest"},
}

METRICS = (("rel_rmse", "rel. RMSE"), ("mare", "MARE"))

CSV_FIELDS = [
    "scene", "method", "role", "budget_s", "rep", "seed", "status", "spp", "render_wall_s", "render_reported_s",
    "preprocess_wall_s", "preprocess_reported_s", "total_s", "rel_rmse", "mare", "nrmse", "ref_spp",
    "ref_noise_rel_rmse", "threads", "width", "height", "load_avg_1m", "render_cmd", "preprocess_cmd", "note",
]

CSV_HEADER = """# firstshot-bench results: one row per run. role: baseline | firstshot | other.
# total_s = preprocess_wall_s + render_wall_s (wall times of the whole processes; *_reported_s: the tools' own timers).
# rel_rmse = sqrt(mean(((x-r)/(r+eps))^2)), mare = mean(|x-r|/(r+eps)), nrmse = RMSE/mean(r); over all pixels and RGB
# channels, x: image, r: reference (ref_spp, see reference.json), eps = 0.01*mean(r). ref_noise_rel_rmse: the
# reference's own estimated error. load_avg_1m: the machine's 1-minute load average when the run started.
"""


def split_method(name):
    """'path+firstshot' -> ('path', True); 'irradiance-cache' -> ('irradiance-cache', False)."""
    if name.endswith(FIRSTSHOT_SUFFIX):
        return name[: -len(FIRSTSHOT_SUFFIX)], True
    return name, False


def method_spec(name, overrides=None, appended=None, baselines=None):
    """The Method that @p name runs.

    A name in METHODS has its registered integrator and arguments; another name is an integrator (NAME) or an
    integrator with a first-shot table (NAME+firstshot) with DEFAULT_METHOD_ARGS of that integrator.
    overrides ({name: args}, from --method-args NAME=ARGS) replace the arguments of method NAME (for a name not
    in METHODS, also an integrator's); appended ({name: args}, from NAME+=ARGS) are added after them.
    baselines: the names that count as baselines (default: METHODS' own flags).
    """
    overrides, appended = overrides or {}, appended or {}
    if name in METHODS:
        reg = METHODS[name]
        integrator, firstshot, args, about = reg.integrator, reg.firstshot, reg.args, reg.about
    else:
        integrator, firstshot = split_method(name)
        args = overrides.get(integrator, DEFAULT_METHOD_ARGS.get(integrator, []))
        about = f"integrator {integrator}" + (" with first-shot" if firstshot else "")
    if name in overrides:
        args = overrides[name]
    args = list(args) + list(appended.get(name, []))
    if baselines is None:
        baseline = name in METHODS and METHODS[name].baseline
    else:
        baseline = name in baselines
    return Method(integrator, args, firstshot, baseline and not firstshot, about)


def method_role(spec):
    return "firstshot" if spec.firstshot else "baseline" if spec.baseline else "other"


def parse_method_args(items):
    """--method-args items: NAME=ARGS replaces, NAME+=ARGS appends. Returns (overrides, appended)."""
    overrides, appended = {}, {}
    for item in items:
        name, sep, rest = item.partition("=")
        if not sep or not name:
            sys.exit(f"firstshot-bench: --method-args wants NAME=ARGS or NAME+=ARGS, got {item!r}")
        if name.endswith("+"):
            appended.setdefault(name[:-1], []).extend(shlex.split(rest))
        else:
            overrides[name] = shlex.split(rest)
    return overrides, appended


def parse_list(text, kind=float):
    return [kind(x) for x in text.split(",") if x.strip()]


def rotated(items, k):
    """items rotated left by k (interleaving: each run starts with a different method)."""
    if not items:
        return []
    k %= len(items)
    return items[k:] + items[:k]


def spec_of(name, args):
    return method_spec(name, args.method_overrides, args.method_appended, args.baselines)


def scene_default(scene_name, key):
    return SCENE_DEFAULTS.get(scene_name, FALLBACK_DEFAULTS).get(key, FALLBACK_DEFAULTS[key])
