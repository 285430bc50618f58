#pragma once
// The offline clock (issue 45): the live instrument (Instrument.h) driven by a motion file's rows
// — `armadillo render`. Each row is one control step of the same instrument `play` and the app
// run (the stage, the one step, the left arm, the publisher), its sample handed to the step as
// the source's own (ControlStep::recorded, in full precision, none dropped); the audio between two
// rows is rendered after the first row's step, block by block, with the recording and the MIDI
// notes it hears, as the live app's audio thread would hear it. Sample 0 is the first row's time.
// The result is the same for the same inputs and seed.
//
// What the render is given and gives back, and the checks it makes before it starts, are the
// engine's (Engine/RenderSettings.h); what plays is described once: one scene (the settings'
// engine) or a set list's cues with the times the cues change.
#include "Engine/RenderSettings.h"
#include "Live/Stage/SetList.h"
#include <vector>

namespace armadillo::live {

/// Runs the scene (settings.engine) over the motion table (IMU, quaternion or pose file); throws
/// InputError for a file that is not a motion file, for two arms (settings.leftMotion) without
/// EngineConfig::twoArms, and for a recording or MIDI notes the scene does not hear.
engine::RenderResult renderOffline(const core::CsvTable& motion, const engine::RenderSettings& settings);

/// `armadillo render --setlist`: the set list's cues in place of one scene; starts at cue 0 and
/// changes cue at the given times (sorted by time here; each requested before the row at or after
/// its time, cross-faded as on stage). Honours the settings' audioIn (every listening cue hears it;
/// InputError when no cue listens), midiIn, leftMotion (two arms: every cue's engine hears both;
/// leftTactile and both orientations are filled), mount and leftMount, onStep (the current cue's
/// engine) and audioSink. InputError naming the set list for a cue index it does not have.
engine::RenderResult renderOffline(const core::CsvTable& motion, const engine::RenderSettings& settings, const SetList& list,
                                   std::vector<CueChange> changes);

} // namespace armadillo::live
