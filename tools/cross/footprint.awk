# SPDX-License-Identifier: GPL-3.0-or-later
# A GNU ld map file's input sections summed by where they come from: text (code and read-only
# data, in flash), data (initialized, in flash and RAM) and bss (zeroed RAM), per archive
# (libstabdae.a, libgsl.a, ...; newlib's and GCC's as "C runtime", the program's own objects as
# "program"). Reads only what follows "Linker script and memory map" (the sections kept).
# Usage: awk -f footprint.awk PROGRAM.map  -> one Markdown row per origin, then the total
function hex(s,    i, v) { # mawk has no strtonum
  v = 0
  for (i = 3; i <= length(s); i++) v = v * 16 + index("0123456789abcdef", substr(s, i, 1)) - 1
  return v
}
function origin(file,    a) {
  if (file ~ /\.a\(/) { sub(/\(.*/, "", file); n = split(file, a, "/"); file = a[n] }
  else return "program"
  if (file ~ /^lib(c|m|g|gcc|rdimon|nosys)(_nano)?\.a$/) return "C runtime"
  return file
}
function add(section, size, file,    o, kind) {
  if (section ~ /^\.(text|rodata|ARM\.ex)/ || section ~ /^\.glue_7/) kind = "text"
  else if (section ~ /^\.data/ || section ~ /^\.(init|fini|preinit)_array/) kind = "data"
  else if (section ~ /^\.bss/ || section == "COMMON") kind = "bss"
  else return
  if (file ~ /crt[a-z0-9]*\.o$/) o = "C runtime"
  else o = origin(file)
  sum[o, kind] += size
  seen[o] = 1
}
/^Linker script and memory map/ { on = 1; next }
!on { next }
/^ \*fill\*/ { pending = ""; next }
/^ [.A-Za-z_][^ ]*$/ { pending = $1; next }  # a long section name, its numbers on the next line
/^ [.A-Za-z_][^ ]* +0x[0-9a-f]+ +0x[0-9a-f]+ +[^ ]/ { add($1, hex($3), $4); pending = ""; next }
pending != "" && /^ +0x[0-9a-f]+ +0x[0-9a-f]+ +[^ ]/ { add(pending, hex($2), $3); pending = ""; next }
{ pending = "" }
END {
  printf "| origin | text | data | bss |\n|---|---:|---:|---:|\n"
  m = split("libstabdae.a libgsl.a libgslcblas.a libamd.a libldl.a libsuitesparseconfig.a program",
            names, " ")
  names[m + 1] = "C runtime"
  for (i = 1; i <= m + 1; i++) {
    o = names[i]
    if (!(o in seen)) continue
    printf "| %s | %d | %d | %d |\n", o, sum[o, "text"], sum[o, "data"], sum[o, "bss"]
    t += sum[o, "text"]; d += sum[o, "data"]; b += sum[o, "bss"]
  }
  printf "| all | %d | %d | %d |\n", t, d, b
}
