#!/bin/sh
# The language server benchmark beside `ruff server` (issue 29): installs ruff from PyPI in a
# virtual environment under target/, then runs `cargo bench --bench lsp_bench`, which drives
# holoc's server on a generated scene and ruff's on a generated Python file of as many lines,
# with the same client and the same edits, and prints both.
#
#   benches/lsp_vs_ruff.sh                          # 5,000 lines, 10,000 edits, the office floor
#   LSP_BENCH_SHAPE=apartments LSP_BENCH_EDITS=3000 benches/lsp_vs_ruff.sh
#
# Without python3 (or without network for pip), the benchmark runs without the comparison.
set -eu
cd "$(dirname "$0")/.."
venv=target/ruff-venv
if [ ! -x "$venv/bin/ruff" ]; then
    if python3 -m venv "$venv" && "$venv/bin/pip" install --quiet ruff; then
        :
    else
        echo "lsp_vs_ruff: ruff could not be installed; running without the comparison" >&2
    fi
fi
if [ -x "$venv/bin/ruff" ]; then
    LSP_BENCH_RUFF="$PWD/$venv/bin/ruff"
    export LSP_BENCH_RUFF
fi
exec cargo bench --bench lsp_bench
