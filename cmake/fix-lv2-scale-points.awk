# Debian's JUCE 7.0.5 writes each scale point of a discrete parameter in dsp.ttl with its
# normalised value (i/(N-1)) while the parameter's range, and the values hosts send, are in the
# parameter's own units (convertFrom0to1), so LV2 hosts label the choices wrongly (JUCE's newer
# releases write convertFrom0to1 of it). Run after JUCE's juce_lv2_helper (Source/Plugin/
# CMakeLists.txt): each scale point value v becomes minimum + v·(maximum − minimum), exact for
# the linear ranges every discrete parameter here has (choices 0..N−1, booleans 0..1).
/^[ \t]*lv2:minimum / { v = $2; sub(/[ \t;]+$/, "", v); lo = v + 0 }
/^[ \t]*lv2:maximum / { v = $2; sub(/[ \t;]+$/, "", v); hi = v + 0 }
/lv2:scalePoint \[/ { inScale = 1 }
inScale && /rdf:value/ {
    match($0, /rdf:value [-+0-9.eE]+/)
    norm = substr($0, RSTART + 10, RLENGTH - 10) + 0
    value = lo + norm * (hi - lo)
    # JUCE prints the normalised value with 6 digits: snap to a whole number when that is what it was
    nearest = int(value + (value >= 0 ? 0.5 : -0.5))
    span = hi - lo; if (span < 0) span = -span; if (span < 1) span = 1
    if ((value - nearest) ^ 2 < (1e-5 * span) ^ 2) text = sprintf("%d", nearest); else text = sprintf("%.6g", value)
    sub(/rdf:value [-+0-9.eE]+/, "rdf:value " text)
}
/\] \.[ \t]*$/ { inScale = 0 }
{ print }
