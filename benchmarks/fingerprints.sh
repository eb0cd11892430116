#!/usr/bin/env bash
# Behaviour fingerprints of the engine: run before and after any engine change; every line
# must stay identical:  benchmarks/fingerprints.sh | diff - benchmarks/fingerprints.txt
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build -q --release -p multibots-core --examples
bin=target/release/examples
echo "paper_table margin 0: $($bin/paper_table | md5sum | cut -d' ' -f1)"
echo "paper_table margin 8: $($bin/paper_table 8 | md5sum | cut -d' ' -f1)"
echo "builtins_table: $($bin/builtins_table | md5sum | cut -d' ' -f1)"
fp() { # scenario steps warmup
  $bin/scale "$1" "$2" "$3" | python3 -c 'import json,sys; d=json.load(sys.stdin); print(d["fingerprint"], d["delivered"], d["s"], d["c"])'
}
for size in paper small large huge; do
  echo "$size 1000+100: $(fp benchmarks/sizes/$size.toml 1000 100)"
done
echo "large 3000+100: $(fp benchmarks/sizes/large.toml 3000 100)"
echo "huge 200+100: $(fp benchmarks/sizes/huge.toml 200 100)"
echo "lifelong-1000 2000+0: $(fp benchmarks/sizes/lifelong-1000.toml 2000 0)"
echo "people 2000+100: $(fp benchmarks/sizes/people.toml 2000 100)"
for traffic in gate reserve; do
  sed "s/^traffic = .*/traffic = \"$traffic\"/" scenarios/warehouse-1000.toml > "${TMPDIR:-/tmp}/mb-fp-$traffic.toml"
  echo "warehouse-1000 $traffic 3000+0: $(fp "${TMPDIR:-/tmp}/mb-fp-$traffic.toml" 3000 0)"
done

