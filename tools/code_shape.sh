#!/usr/bin/env bash
# The shape of the code in include/ and src/: the functions longer than N lines (default 60), the
# longest one, and the largest files (default 5). Function extents are Universal Ctags' end lines
# (Debian universal-ctags). Usage: tools/code_shape.sh [N [FILES]]
set -eu
n=${1:-60}
files=${2:-5}
cd "$(dirname "$0")/.."
command -v ctags >/dev/null || { echo "code_shape: needs universal-ctags (apt-get install universal-ctags)" >&2; exit 1; }
lengths=$(ctags -R --languages=C++ --langmap=C++:+.hpp --kinds-C++=fp --fields=+ne -x \
  --_xformat='%{line} %{end} %{input} %{name}' include src 2>/dev/null |
  awk '$2 != "" { print $2 - $1 + 1, $3 ":" $1, $4 }' | sort -k1,1rn -k2,2)
echo "functions over $n lines (lines, place, name):"
awk -v n="$n" '$1 > n { print "  " $0 }' <<<"$lengths"
echo "longest function:"
awk 'NR == 1 { print "  " $0 }' <<<"$lengths"
echo "largest files (lines):"
find include src -type f \( -name '*.hpp' -o -name '*.cpp' \) -exec wc -l {} + | awk '$2 != "total"' |
  sort -k1,1rn -k2,2 | awk -v m="$files" 'NR <= m { print "  " $0 }'
