# Shared by the scripts/bench-*.sh benchmarks (sourced, not run).

# machine_line: the machine and its load as every benchmark reports them, on one line.
machine_line() {
  echo "machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'), $(date -u +%F), load average $(cut -d' ' -f1-3 /proc/loadavg)"
}

# median VALUE...: the median (the lower middle one of an even count).
median() { printf '%s\n' "$@" | sort -g | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}'; }
