#pragma once
// The plugin's saved state: the parameters (host-automatable, AudioProcessorValueTreeState) and
// the settings (ports, files, text, layout: a ValueTree), read back with validation so a damaged,
// hand-edited or future state never puts nonsense into the sockets or the engine.
//
// Threads: the message thread and the host's state calls (getStateInformation /
// setStateInformation, which hosts make from a non-audio thread). Never the audio thread.
#include "Live/Outputs/MappingSession.h"
#include "Live/Outputs/MessagesRig.h"
#include "Live/Outputs/TactorRig.h"
#include <juce_audio_processors/juce_audio_processors.h>

namespace armadillo::plugin {

/// Names of the persistent settings (the "SETTINGS" child of the saved state).
namespace SettingIds {
inline const juce::Identifier root {"SETTINGS"};
inline const juce::Identifier oscOutEnabled {"oscOutEnabled"};
inline const juce::Identifier oscOutHost {"oscOutHost"};
inline const juce::Identifier oscOutPort {"oscOutPort"};
inline const juce::Identifier oscInEnabled {"oscInEnabled"};
inline const juce::Identifier oscInPort {"oscInPort"};
inline const juce::Identifier oscInFormat {"oscInFormat"};   ///< "" = detect; else docs/SENSORS.md names
inline const juce::Identifier oscInMount {"oscInMount"};     ///< "" = the format's usual mount; a preset or mount file
inline const juce::Identifier serialPort {"serialPort"};
inline const juce::Identifier baudRate {"baudRate"};
inline const juce::Identifier calibrationFile {"calibrationFile"};
inline const juce::Identifier armSide {"armSide"};           ///< "right" | "left"
inline const juce::Identifier backMotors {"backMotors"};     ///< bool: 12 motors instead of 9
inline const juce::Identifier brailleText {"brailleText"};
inline const juce::Identifier score {"score"};               ///< "rite-of-spring" | "polytope"
inline const juce::Identifier midiChannel {"midiChannel"};   ///< 1..16
inline const juce::Identifier editorWidth {"editorWidth"};
inline const juce::Identifier editorHeight {"editorHeight"};
inline const juce::Identifier simWandering {"simWandering"};
inline const juce::Identifier connectOnStart {"connectOnStart"}; ///< bool: open the saved port when source = device
inline const juce::Identifier readerVoice {"readerVoice"};   ///< "auto" | "on" | "off": self-voicing and braille display (ReaderVoice.h)
inline const juce::Identifier speechRate {"speechRate"};     ///< −100..100, 0 = the voice's default
inline const juce::Identifier armFeedback {"armFeedback"};   ///< bool: training feedback felt on the arm (Access/Feedback.h)
inline const juce::Identifier touchProfile {"touchProfile"}; ///< the reader's touch profile (its JSON, Link/TouchProfile.h), "" = none
inline const juce::Identifier setList {"setList"};           ///< the set list's text (docs/STAGE.md JSON), "" = none
inline const juce::Identifier setListName {"setListName"};   ///< the file it came from (for messages)
inline const juce::Identifier cueNextNote {"cueNextNote"};   ///< MIDI note that steps to the next cue, −1 = none (Stage.h)
inline const juce::Identifier cuePrevNote {"cuePrevNote"};   ///< MIDI note that steps back, −1 = none
inline const juce::Identifier stageOscEnabled {"stageOscEnabled"}; ///< bool: listen for OSC stage commands (docs/STAGE.md)
inline const juce::Identifier panicGesture {"panicGesture"}; ///< bool: the arm hanging down for 2 s panics (docs/STAGE.md)
inline const juce::Identifier stageOscPort {"stageOscPort"}; ///< their UDP port (0: any free port)
inline const juce::Identifier stageOscBind {"stageOscBind"}; ///< the address they are heard on ("127.0.0.1": this machine only; docs/SECURITY.md)
inline const juce::Identifier stageOscAllow {"stageOscAllow"}; ///< senders allowed, ADDR[/BITS],… ("": everyone who reaches stageOscBind)
inline const juce::Identifier leftArmOsc {"leftArmOsc"};     ///< bool: an OSC sender as the left arm (docs/STAGE.md "Two arms")
inline const juce::Identifier leftArmOscPort {"leftArmOscPort"}; ///< its UDP (and TCP) port, 1..65535 (9003)
// The app's adaptive braille training (Procedures/AdaptiveTraining.h; the CLI's --trials --stages --method --level)
inline const juce::Identifier adaptiveTrials {"adaptiveTrials"};   ///< 1..10000 (20)
inline const juce::Identifier adaptiveStages {"adaptiveStages"};   ///< comma list of letters, words, signs, contractions
inline const juce::Identifier adaptiveMethod {"adaptiveMethod"};   ///< rows | whole | columns | dots
inline const juce::Identifier adaptiveLevel {"adaptiveLevel"};     ///< 1..15 (8)
inline const juce::Identifier readerProfile {"readerProfile"};     ///< the reader profile file (Access/ReaderProfile.h), "" = none
// The tactor rig (issue 33, docs/TACTORS.md): the plugin's Tactors bus and the app's tactor output
inline const juce::Identifier tactorModel {"tactorModel"};     ///< "erm" | "lra" | "voice-coil"
inline const juce::Identifier tactorMap {"tactorMap"};         ///< the channel map's text ("" = channel k plays motor k)
inline const juce::Identifier tactorGains {"tactorGains"};     ///< a gain file's path ("" = none)
inline const juce::Identifier tactorSound {"tactorSound"};     ///< bool: a voice coil carries the scene's own sound
inline const juce::Identifier tactorOutput {"tactorOutput"};   ///< bool: the app's tactor output on
inline const juce::Identifier tactorDevice {"tactorDevice"};   ///< the app's: "jack" or an ALSA PCM ("hw:UMC1820")
inline const juce::Identifier tactorConnect {"tactorConnect"}; ///< the app's, JACK: connect tactor_k to ports matching this
// Messages on the arm over MQTT (issue 35, docs/MQTT.md "In the app")
inline const juce::Identifier mqttEnabled {"mqttEnabled"};     ///< bool: connect (on start too)
inline const juce::Identifier mqttBroker {"mqttBroker"};       ///< HOST[:PORT] ("localhost:1883")
inline const juce::Identifier mqttTopics {"mqttTopics"};       ///< topic filters, comma-separated ("arm/inbox")
inline const juce::Identifier mqttUrgent {"mqttUrgent"};       ///< topic filters whose messages interrupt
inline const juce::Identifier mqttConfig {"mqttConfig"};       ///< a configuration file (docs/MQTT.md), "" = none
inline const juce::Identifier messageDisplay {"messageDisplay"}; ///< "roll" | "timed"
// The web page (issue 47, docs/INTERFACES.md "The web page (HTTP)"; closed by default)
inline const juce::Identifier webEnabled {"webEnabled"};       ///< bool: serve the page (on start too)
inline const juce::Identifier webPort {"webPort"};             ///< int: TCP port, 0 = a free port
inline const juce::Identifier webBind {"webBind"};             ///< "" = loopback only; else a numeric address (then a token)
} // namespace SettingIds

namespace PluginState {

inline constexpr int kVersion = 1;   ///< the saved state's format version
/// The longest set list text kept in the state (other text settings keep 4096 characters).
inline constexpr int kMaxSetListChars = 1 << 20;

/// Every setting with its default value.
juce::ValueTree defaultSettings();
/// Writes into `settings` the known properties of `loaded` that have the right kind and range,
/// the defaults for the rest (an invalid `loaded` gives all defaults).
void installSettings(juce::ValueTree& settings, const juce::ValueTree& loaded);
/// Parameters, settings and the mapping set (`mapping`: the MAPPING node, MappingSession.h;
/// left out when invalid) as the host stores them.
void save(juce::AudioProcessorValueTreeState& parameters, const juce::ValueTree& settings, juce::MemoryBlock& dest,
          const juce::ValueTree& mapping = {});
/// Restores what save() wrote. Returns "" when all was taken, else what was refused and that
/// defaults were used instead (for the status line). Never throws; any bytes are safe.
/// `mapping` (when given) receives the saved MAPPING node, or an invalid tree when the state has
/// none (a state from before the mapping, or one that was refused): the caller validates it.
juce::String restore(juce::AudioProcessor& processor, juce::AudioProcessorValueTreeState& parameters,
                     juce::ValueTree& settings, const void* data, int sizeInBytes, juce::ValueTree* mapping = nullptr);
/// The MAPPING node (docs/PLUGIN.md "State") of a mapping session's saved set, and back (an
/// invalid node: a state from before the mapping).
juce::ValueTree mappingNode(const live::SavedMapping& saved);
live::SavedMapping savedMapping(const juce::ValueTree& node);
/// Every parameter and setting back to its default.
void resetToDefaults(juce::AudioProcessor& processor, juce::ValueTree& settings);

/// A whole setup (scene, parameters, source, device port and calibration, mount, OSC) as a
/// readable XML file (the state document of docs/PLUGIN.md), written whole or not at all.
/// Returns "" or why it could not be written.
juce::String writeSetupFile(const juce::MemoryBlock& state, const juce::File& file);
/// Reads a setup file back into the bytes restore() takes. Returns "" or why it is not a setup
/// (restore() then still validates every value).
juce::String readSetupFile(const juce::File& file, juce::MemoryBlock& state);

/// The tactor and MQTT settings as the instrument's parts take them (Live/Outputs/TactorRig.h,
/// Live/Outputs/MessagesRig.h).
live::TactorSettings tactorSettings(const juce::ValueTree& settings);
live::MessagesSettings messagesSettings(const juce::ValueTree& settings);

} // namespace PluginState

} // namespace armadillo::plugin
