# tools/f90deps.awk: prints "build/a.o: build/b.o" for each in-tree module b used by src/d/a.f90,
# and "build/a.o: src/d/x.inc" for each file src/d/a.f90 includes (found beside it, as gfortran
# finds it). Objects are named by file name alone: two sources of one name clash.
# Run: awk -f tools/f90deps.awk $(find src -name '*.f90') > deps.mk (the Makefile rewrites build/).
{ line = tolower($0); sub(/!.*/, "", line); n = split(line, w, /[ \t,:]+/) }
w[1] == "" { for (i = 1; i < n; i++) w[i] = w[i+1]; n-- }
w[1] == "module" && w[2] !~ /^(procedure|subroutine|function)$/ && n >= 2 { defined[w[2]] = FILENAME }
w[1] == "use" && w[2] != "intrinsic" && n >= 2 { uses[FILENAME, w[2]] = 1 }
w[1] == "include" && n >= 2 { inc = w[2]; gsub(/["']/, "", inc); incs[FILENAME, inc] = 1 }
END { for (k in incs) { split(k, p, SUBSEP); print obj(p[1]) ": " folder(p[1]) p[2] }
 for (k in uses) { split(k, p, SUBSEP); m = p[2]
        if ((m in defined) && defined[m] != p[1]) print obj(p[1]) ": " obj(defined[m]) } }
function obj(f) { sub(/^.*\//, "", f); sub(/\.[fF]90$/, ".o", f); return "build/" f }
function folder(f) { if (f !~ /\//) return ""; sub(/[^\/]*$/, "", f); return f }
