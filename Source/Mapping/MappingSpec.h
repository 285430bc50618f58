#pragma once
// The mapping matrix (issue 23, docs/MAPPING.md): what a mapping file says, as plain data a UI can
// edit and a file can hold. A *mapping* takes one source through one transform to one
// destination; a MappingDocument is any number of them side by side, plus the learned postures
// they may name. Nothing here is real-time: documents are parsed, edited, saved and compiled
// (Mapping/Mapper.h: MappingSet::build) off the audio thread.
//
// File format: JSON, `"version": 1`, read with the project's line-numbered JSON reader; every
// error names the file, line and column (InputError, exit code 3). The contract subset is in
// docs/INTERFACES.md, the whole format in docs/MAPPING.md.
#include "Core/StageCommand.h"
#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace armadillo::mapping {

inline constexpr int kMappingFileVersion = 1;
inline constexpr int kMaxArms = 2;           ///< a source names an arm: 0 = the right arm (or the only one), 1 = the left arm
inline constexpr int kMacroCount = 8;        ///< the plugin's generic parameters macro1…macro8
inline constexpr int kMaxTablePoints = 16;   ///< curve "table": at most this many [in, out] points
inline constexpr int kMaxZones = 18;         ///< zones per mapping (18: one per knob of the virtual control panel)
inline constexpr int kMaxOscArgs = 8;        ///< arguments of one templated OSC message
inline constexpr int kMaxMappings = 256;     ///< mappings in one document (the file is refused beyond)

/// Default hysteresis for zones and thresholds on angle sources, degrees (docs/MAPPING.md):
/// a zone is left only once the source is this far past its border (and a threshold crossed
/// back only this far below it). Between 1.5° and 5° (issue 23): larger than the fusion's
/// jitter at rest, smaller than a deliberate move.
inline constexpr double kDefaultHysteresisDeg = 3.0;
/// Default hysteresis for sources that are not angles: this fraction of the `in` span.
inline constexpr double kDefaultHysteresisFraction = 0.03;
/// Default length of a note triggered by a gesture (the plugin's classic wiring, docs/PLUGIN.md).
inline constexpr double kDefaultGestureNoteMs = 50.0;

// ---------------------------------------------------------------------------------------------
// Sources

/// What a mapping reads. Continuous sources give a value at every control update; event sources
/// (Gesture, Posture) give enter/leave or trigger events, and Posture also a continuous closeness.
enum class SourceKind : std::uint8_t {
    Elevation,      ///< "elevation": forearm axis above horizontal, deg, −90…90 (INTERFACES.md "Pose")
    Azimuth,        ///< "azimuth": clockwise from north, deg, 0…360 (wraps; relative to forward with "forward": true)
    Roll,           ///< "roll": deg, −180…180
    Yaw,            ///< "yaw": −(azimuth − forward) wrapped to ±180°, counter-clockwise seen from above positive
    Pitch,          ///< "pitch": = elevation, deg
    QuatW,          ///< "qw": orientation quaternion (device → earth), w component (sign chosen so w ≥ 0)
    QuatX,          ///< "qx"
    QuatY,          ///< "qy"
    QuatZ,          ///< "qz"
    AngularSpeed,   ///< "speed": |ω|, deg/s
    FluxFace,       ///< "fluxFace": face normal · ω, deg/s (thesis §2.6.3)
    FluxEdge,       ///< "fluxEdge": edge normal · ω, deg/s (thesis §2.6.3)
    RollTrigger,    ///< "rollTrigger": (x·ω)/√(flux₁²+flux₂²), dimensionless (thesis §2.6.3)
    Punch,          ///< "punch": forearm-axis acceleration while ω is small, m/s² (thesis §2.6.3)
    ScenePitch,     ///< "scene.pitch": the theremin's sounding pitch as a MIDI note number (fractional); none elsewhere
    SceneFret,      ///< "scene.fret": the theremin's fret index (0 = lowest); none elsewhere
    SceneStrike,    ///< "scene.strike": the cymbal's last strike speed, deg/s (0 before any); none elsewhere
    Gesture,        ///< "gesture:NAME": a scene's gesture (roll, punch, strike, fret, select, …; "gesture:*" any,
                    ///< "gesture:other" any gesture no other mapping of the document names). Event; value = the gesture's value
    Posture,        ///< "posture:NAME": a learned posture (Mapping/Posture.h): enter/leave events, value = closeness 0…1
    GestureValue,   ///< "value": only inside an AuxSpec of an event mapping: the event's own value (a gesture's value)
    YprQuatW,       ///< "ypr.qw": the quaternion of (yaw, pitch, roll) above as q = qz(yaw)·qy(pitch)·qx(roll)
    YprQuatX,       ///< "ypr.qx"   (axes x forward, y left, z up: IEM SceneRotator's default sequence
    YprQuatY,       ///< "ypr.qy"    "roll → pitch → yaw", extrinsic; w ≥ 0)
    YprQuatZ,       ///< "ypr.qz"
    // Relative sources (two arms, docs/MAPPING.md "Two arms"): no value unless both arms are tracked.
    ArmsAngle,      ///< "arms.angle": the angle between the two forearm axes (device x in earth), deg, 0…180
    ArmsRoll,       ///< "arms.roll": left roll − right roll wrapped to ±180°, deg
    ArmsRaised,     ///< "arms.raised": "both arms raised", a gate: its value is the lower of the two elevations
                    ///< (deg); always read with a threshold (default kDefaultArmsRaisedDeg) and its hysteresis
    // The virtual control panel's state (the panel scene, thesis §3.4; none elsewhere): the panel as a remote.
    PanelKnob,      ///< "panel.knob": the knob under the arm, a whole number 0..17 (0..8 upper level, 9..17 lower)
    PanelLevel,     ///< "panel.level": the level the arm is on, 1 upper, 0 lower
    PanelSelected,  ///< "panel.selected": the knob last selected by a quick roll, 0..17; no value before the first
};

/// "arms.raised" without a "threshold": both elevations at or above this many degrees (above the
/// horizontal) is "raised"; it ends once either falls below it less the hysteresis (default 3°).
inline constexpr double kDefaultArmsRaisedDeg = 30.0;

struct SourceSpec {
    SourceKind kind = SourceKind::Elevation;
    std::string name;   ///< Gesture: the gesture name ("*", "other"); Posture: the posture name; else empty
    /// Arm sources (isArmSource): 0 = the right arm, or the only one (unprefixed names); 1 = the
    /// left arm ("left." names, or "arm": "left"). Other sources: always 0.
    int arm = 0;
};

/// The file's spelling of a source ("elevation", "left.roll", "arms.angle", "gesture:punch",
/// "posture:up").
std::string sourceName(const SourceSpec& s);
/// Parses a source name; false for an unknown one. "left.NAME" is the left arm's NAME for every
/// arm source; "right.NAME" is accepted for NAME (the right arm, or the only one).
bool parseSourceName(std::string_view text, SourceSpec& out);
/// True for sources read from one arm's state (elevation … punch, qw…qz, ypr.q*): these exist
/// per arm. Scene outputs, gestures, postures and the relative arms.* sources do not.
bool isArmSource(SourceKind k) noexcept;
/// True for the relative sources (arms.angle, arms.roll, arms.raised): both arms or no value.
bool isTwoArmSource(SourceKind k) noexcept;
/// True for Gesture and Posture (they drive events); zones and thresholds turn any continuous
/// source into events too (MappingSpec::zones, TransformSpec::threshold).
bool isEventSource(SourceKind k) noexcept;
/// True for sources measured in degrees (the default hysteresis is then kDefaultHysteresisDeg).
bool isAngleSource(SourceKind k) noexcept;
/// True for the panel's whole-number sources (panel.knob, panel.level, panel.selected): they step
/// by 1 and the panel scene already holds them with its own hysteresis (a knob is left 10 % of a
/// width past its edge, a level ±levelAngle), so their default hysteresis is 0 — a zone
/// [k − 0.5, k + 0.5] is then exactly knob k.
bool isSteppedPanelSource(SourceKind k) noexcept;
/// The pitch classes of a TransformSpec::scale above its root (bit k = k semitones); 0 = unknown name.
int scaleMask(const std::string& name);
/// The natural range of a continuous source, the `in` default: elevation/pitch [−90, 90],
/// azimuth [0, 360], roll/yaw [−180, 180], quaternion [−1, 1], speed/flux [0|−720, 720] deg/s,
/// rollTrigger [−5, 5], punch [−20, 20] m/s², scene.pitch [0, 127], scene.fret [0, 24],
/// scene.strike [0, 1000], posture [0, 1], arms.angle [0, 180], arms.roll [−180, 180],
/// arms.raised [−90, 90], panel.knob and panel.selected [0, 17], panel.level [0, 1]; a left-arm
/// source as its right-arm name.
void defaultInputRange(SourceKind k, double& lo, double& hi) noexcept;

/// A second, auxiliary source: velocity from a source, MPE per-note expressions. Normalised
/// over [lo, hi] (clamped) to 0…1.
struct AuxSpec {
    bool used = false;
    SourceSpec source {};
    double lo = 0.0, hi = 1.0;
    bool abs = false;   ///< take |value| first (gesture values may be signed)
};

// ---------------------------------------------------------------------------------------------
// Transform

enum class Curve : std::uint8_t {
    Linear,   ///< "linear"
    Exp,      ///< "exp": (e^(shape·x) − 1)/(e^shape − 1); shape > 0 slow start, < 0 fast start; 0 = linear
    Log,      ///< "log": the inverse of Exp with the same shape
    SCurve,   ///< "s": nᵏ/(nᵏ + (1−n)ᵏ) with k = 1 + shape (0 = linear, larger = steeper in the middle)
    Table,    ///< "table": piecewise linear through `table` points [x, y] in normalised 0…1 units
};

/// Applied in this order (docs/MAPPING.md "Transform"): forward reference (azimuth) → one-euro
/// smoothing (on the raw value; angles unwrapped) → dead zone → normalise over `in` (clamped) →
/// invert → curve → quantise to `steps` → scale onto `out` → quantise to a musical scale.
struct TransformSpec {
    bool hasIn = false;                 ///< false: the source's natural range (defaultInputRange)
    double inLo = 0.0, inHi = 1.0;
    bool hasOut = false;                ///< false: the destination's full range
    double outLo = 0.0, outHi = 1.0;    ///< in the destination's unit (CC value, 14-bit value, semitones, 0…1 …)
    bool invert = false;
    bool abs = false;                   ///< |value| before anything else (signed gesture values, fluxes)
    bool forward = false;               ///< azimuth: measured from the forward reference, wrapped to 0…360
    Curve curve = Curve::Linear;
    double shape = 3.0;                 ///< Exp/Log/SCurve steepness
    std::vector<std::array<double, 2>> table;   ///< Table: [x, y] points, x increasing, both 0…1; ≤ kMaxTablePoints

    // One-euro filter (Casiez, Roussel & Vogel, CHI 2012). Off while minCutoffHz is 0.
    // "smoothMs": T sets minCutoffHz = 1/(2πT) (the time constant of the filter at rest).
    double minCutoffHz = 0.0;           ///< Hz; 0 = no smoothing
    double beta = 0.0;                  ///< cutoff increase per unit/s of speed (less lag when moving)
    double derivativeCutoffHz = 1.0;    ///< Hz, the speed estimate's own low-pass

    double deadZone = 0.0;              ///< source units: values within ± this of the centre of `in` read as the centre
    double hysteresis = -1.0;           ///< source units for zones and thresholds; < 0 = the default (kDefaultHysteresis…)
    bool hasThreshold = false;          ///< a continuous source becomes an event: on above, off below (with hysteresis)
    double threshold = 0.0;             ///< source units
    int steps = 0;                      ///< > 1: quantise the normalised value to this many equal steps
    std::string scale;                  ///< quantise the output (semitones) to a scale: "chromatic", "major", "minor",
                                        ///< "pentatonic", "minor-pentatonic", "dorian", "whole-tone", "blues"; "" = none
    int scaleRoot = 0;                  ///< the scale's root pitch class 0…11 (0 = C)
};

// ---------------------------------------------------------------------------------------------
// Zones

/// A region of the source's range (and optionally of elevation: an azimuth/elevation sector).
/// The file's triple [from, to, note] is a zone with value = note; from > to wraps through 360
/// on azimuth/yaw. A zone's events are enter and leave (with the mapping's hysteresis).
struct ZoneSpec {
    double from = 0.0, to = 0.0;        ///< source units; [from, to] (on azimuth/yaw [from, to)); the first listed wins where two meet
    bool hasElevation = false;          ///< a sector: elevation must lie in [elFrom, elTo] too
    double elFrom = -90.0, elTo = 90.0;
    int value = 60;                     ///< the note (notes/MPE), program (program), or number handed to OSC as $zone's value
};

// ---------------------------------------------------------------------------------------------
// Destinations

enum class DestinationKind : std::uint8_t {
    Cc7,             ///< {"midi": "cc", "channel", "cc"}: 0…127
    Cc14,            ///< {"midi": "cc14", "channel", "cc"}: MSB on cc, LSB on cc+32, MSB first (MIDI 1.0 spec);
                     ///< "lsbFirst": true for receivers that latch the value on the MSB, e.g. IEM SceneRotator
                     ///< (IEM plug-in suite, SceneRotator/Source/PluginProcessor.cpp, processBlock: CC 48…50 store
                     ///< the LSB, CC 16…18 then apply (128·MSB + LSB)/16384). 0…16383
    Nrpn,            ///< {"midi": "nrpn", "channel", "number"}: CC 99/98 (parameter MSB/LSB), 6/38 (value MSB/LSB); 0…16383
    PitchBend,       ///< {"midi": "pitchbend", "channel"}: 0…16383 (8192 = centre)
    ChannelPressure, ///< {"midi": "pressure", "channel"}: 0…127
    Notes,           ///< {"midi": "notes", "channel", "velocity", "zones"} zones → note on enter, off on leave;
                     ///< {"midi": "note", "channel", "note", "velocity", "lengthMs"} an event source → a note
    Mpe,             ///< {"midi": "mpe", "zones", "bend", "pressure", "timbre", "members"}: one note per zone on a
                     ///< member channel (lower zone: master channel 1, members 2…), per-note pitch bend/pressure/CC74
    ProgramChange,   ///< {"midi": "program", "channel", "program"}: an event sends `program`; zones send their value;
                     ///< a continuous source sends round(out value) 0…127 when it changes
    Osc,             ///< {"osc": "/address", "args": [...], "host", "port", "types"}: templated message
    Macro,           ///< {"macro": 1…8}: the plugin's macro parameter, 0…1
    SceneParam,      ///< {"param": "theremin.range"}: a scene parameter; 0…1 over its range unless `out` is given
                     ///< (then in the parameter's own unit)
    SetForward,      ///< {"action": "forward"}: an event sets the forward reference to the current azimuth
    Mqtt,            ///< {"mqtt": {"topic", "payload", "qos", "retain", "rate"}}: a templated MQTT message (issue 35,
                     ///< docs/MQTT.md): "{value}", "{round}", "{zone}", "{on}", "{state}" in the payload, "{zone}" and
                     ///< "{arm}" in the topic; sent when it changes, at most `rate` per second per topic (latest kept)
    Stage,           ///< {"stage": "next"|"prev"|"panic"|"resume"} or {"stage": "cue", "cue": N}: an event (its rising
                     ///< edge: a gesture, a posture or zone entered, a threshold crossed upward) steps the set list or
                     ///< panics (docs/STAGE.md); nothing while held, nothing on leaving
};

/// A piece of an MQTT payload template: literal text, then a value of the moment (or nothing).
/// Placeholders are exactly "{value}" (the transformed value, up to 6 significant digits),
/// "{round}" (it rounded to a whole number), "{zone}" (the zone's or gesture's value), "{on}"
/// (1/0), "{state}" ("ON"/"OFF", Home Assistant's spelling) and "{arm}" (0 right, 1 left);
/// every other character, braces of a JSON payload included, is literal.
struct MqttPayloadPart {
    enum class Field : std::uint8_t { None, Value, Round, Zone, On, State, Arm };
    std::string text;
    Field field = Field::None;
};
std::vector<MqttPayloadPart> splitMqttPayload(const std::string& payload);
/// Why a payload template is refused ("" when it is fine): an unknown "{name}" placeholder.
std::string mqttPayloadProblem(const std::string& payload);

/// What a Stage destination does (DestinationSpec::stage) is a core::StageCommand::Kind.
/// The file's spelling: "next", "prev", "cue", "panic", "resume".
const char* stageActionName(core::StageCommand::Kind a) noexcept;

/// One argument of a templated OSC message: a constant or a value of the moment.
struct OscArgSpec {
    enum class Kind : std::uint8_t { Number, String, Value, Source, Zone, On } kind = Kind::Value;
    double number = 0.0;     ///< Number
    std::string text;        ///< String
    SourceSpec source {};    ///< Source: "$elevation", "$yaw", "$qw", … (the raw source value, after the forward reference)
    char type = 'f';         ///< 'f' float32, 'i' int32, 'd' float64, 's' string (from "types" or the constant's kind)
    bool negate = false;     ///< "-$yaw": the value with its sign flipped (an inversion switch for OSC arguments)
};
// File spelling of args: "$value" (the transformed value), "$zone" (the zone's value, or the
// gesture's value for an event), "$on" (1 enter/on, 0 leave/off), "$NAME" (a source, e.g. "$yaw"),
// a number, or any other string (a constant). "{zone}" and "{arm}" in the address are replaced
// when the set is built (one address per zone), so nothing is formatted on the audio thread.

struct DestinationSpec {
    DestinationKind kind = DestinationKind::Cc7;
    int channel = 1;          ///< MIDI channel 1…16 (MPE: the master channel, 1 = lower zone)
    int number = 0;           ///< cc (Cc7/Cc14), parameter (Nrpn 0…16383), note (Notes from events), program, macro 1…8
    bool lsbFirst = false;    ///< Cc14 only
    int velocity = 100;       ///< notes: constant velocity 1…127 (when velocitySource is unused)
    AuxSpec velocitySource {};///< notes/MPE: velocity from a source (1…127 over its range)
    double lengthMs = -1.0;   ///< notes from events: note length; < 0 = default (gestures 50 ms, postures/thresholds until off)
    int mpeMembers = 15;      ///< MPE member channels (master + 1 … master + members)
    AuxSpec mpeBend {};       ///< MPE per-note pitch bend from a source (−1…1 → 0…16383; unused = centre)
    double mpeBendRange = 48; ///< semitones (documentation for the receiver; sent in no message)
    AuxSpec mpePressure {};   ///< MPE per-note channel pressure 0…127
    AuxSpec mpeTimbre {};     ///< MPE per-note CC 74, 0…127
    std::string address;      ///< OSC address template
    std::vector<OscArgSpec> args;   ///< OSC arguments (empty = one float "$value")
    std::string host;         ///< OSC target; empty = the front end's default target (--osc-out, else 127.0.0.1)
    int port = 0;             ///< OSC target port; 0 = the front end's default (9000)
    std::string paramId;      ///< SceneParam: the scene parameter's stable id
    core::StageCommand::Kind stage = core::StageCommand::Kind::CueNext;   ///< Stage: what it does; CueGoto: `number` is the cue (0-based)
    // Mqtt: the topic template is `address`.
    std::string payload = "{value}";   ///< payload template
    int qos = 0;              ///< 0, 1 or 2
    bool retain = false;
    double rate = -1.0;       ///< messages per second for its topic; < 0 = the client's default (MqttConfig::publishRate), 0 = no limit
};

// ---------------------------------------------------------------------------------------------
// Mappings, postures, documents

struct MappingSpec {
    std::string label;        ///< optional, for editors ("filter cutoff")
    SourceSpec source {};
    TransformSpec transform {};
    std::vector<ZoneSpec> zones;   ///< from "zones" (in "to", as the issue's example, or beside it)
    DestinationSpec to {};
    bool muted = false;
};

/// A learned posture (Mapping/Posture.h): held examples of the orientation and a radius.
struct PostureSpec {
    std::string name;
    std::vector<std::array<double, 4>> examples;   ///< unit quaternions (w, x, y, z), device → earth
    double radiusDeg = 20.0;      ///< closeness falls from 1 at an example to 0 at this distance
    double hysteresisDeg = -1.0;  ///< < 0: kDefaultHysteresisDeg
    double maxSpeedDegS = 90.0;   ///< faster than this the arm is moving, not holding a posture
};

struct MappingDocument {
    int version = kMappingFileVersion;
    std::string name;                    ///< optional
    std::vector<MappingSpec> mappings;
    std::vector<PostureSpec> postures;
};

/// Parses a mapping file's text. Throws InputError(sourceName, line, key path, "column C: …")
/// for any syntax or meaning error (unknown source, channel out of range, a zone triple that is
/// not three numbers, an unsupported version, a posture a mapping names but the file lacks, …).
MappingDocument parseMappingDocument(std::string_view text, const std::string& sourceName);
/// The document as JSON text that parseMappingDocument reads back to the same document.
std::string toJson(const MappingDocument& doc);

// ---------------------------------------------------------------------------------------------
// Presets (Resources/Mappings/NAME.json, compiled in; overridable like the other resources)

/// Built-in and user preset names, sorted: classic, mpe, scenerotator, scenerotator-osc, …
std::vector<std::string> presetNames(const std::string& extraDir = {});
/// `--map PRESET|FILE`: a preset name, else a path to a JSON file. InputError for a bad file,
/// IoError when neither a preset nor a readable file has that name.
MappingDocument loadMapping(const std::string& presetOrPath, const std::string& extraDir = {});

} // namespace armadillo::mapping
