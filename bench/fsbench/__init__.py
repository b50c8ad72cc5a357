"""fsbench: the modules of the speed-against-error harness, whose entry point is bench/firstshot_bench.py.

config (method registry, scene defaults, goals, CSV columns, method-name parsing), formatting (text of numbers and
times), analysis (the pure maths: time to a target, ratios, goals, reference rounds, median curves), tools
(running the command-line tools, the results CSV), reference (the progressive cached reference), runner
(benchmarking a scene), report (tables, summary, plots) and accuracy (the preprocessing accuracy report).
Standard library only, plus matplotlib for the plots (imported when plotting).
"""
