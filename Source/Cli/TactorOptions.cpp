#include "Cli/TactorOptions.h"
#include "Core/Errors.h"

namespace armadillo::cli {

std::vector<OptionSpec> tactorOptionSpecs(bool withDevice)
{
    std::vector<OptionSpec> o;
    if (withDevice)
        o.push_back({"--tactors", "DEVICE|jack", "the motor grid live as audio, one channel per motor (docs/TACTORS.md): an ALSA PCM\n"
                                                 "(hw:UMC1820, plughw:1) or jack (output ports tactor_1..tactor_N of client armadillo)"});
    o.push_back({"--tactor-model", "MODEL", "the actuators: erm (carrier 100..250 Hz rising with the level), lra (a sine at\n"
                                            "--tactor-hz, default 170, with a braking pulse at each stop) or voice-coil (a carrier\n"
                                            "at --tactor-hz, default 250); default erm" +
                                                std::string(withDevice ? "" : " (--tactile-wav: voice-coil at 150 Hz)")});
    o.push_back({"--tactor-hz", "HZ", "lra: the resonance (40..400, default 170); voice-coil: the carrier (40..400, default 250)"});
    o.push_back({"--tactor-sound", "", "voice-coil: the scene's own sound is the carrier, band-limited to 40..400 Hz (the cymbal\n"
                                       "felt as its own waveform; silence falls back to the fixed carrier)"});
    o.push_back({"--tactor-map", "MAP", "the motor of each channel, channel 1 first: 1-9 (the default; 1-12 with --back-motors),\n"
                                        "lists and ranges such as 10-12,1-9; - = a silent channel"});
    o.push_back({"--tactor-gain", "FILE.json", "calibration gains per channel, 0..1 (docs/TACTORS.md)"});
    if (withDevice) {
        o.push_back({"--tactor-connect", "PATTERN", "with --tactors jack: connect tactor_k to the k-th JACK input port matching PATTERN\n"
                                                    "(e.g. system:playback_)"});
        o.push_back({"--tactor-rate", "HZ", "with an ALSA device: its sample rate (default 48000; JACK uses the server's)"});
    }
    return o;
}

bool anyTactorSetting(const CommandLine& cl)
{
    for (const char* o : {"--tactor-model", "--tactor-hz", "--tactor-sound", "--tactor-map", "--tactor-gain", "--tactor-connect", "--tactor-rate"})
        if (cl.has(o)) return true;
    return false;
}

live::TactorOutputConfig tactorConfig(const CommandLine& cl, int motors)
{
    live::TactorOutputConfig c;
    c.device = cl.value("--tactors");
    if (cl.has("--tactors") && c.device.empty()) throw UsageError("--tactors needs an ALSA device name or jack");
    if (cl.has("--tactor-model") && !tactors::parseModel(cl.value("--tactor-model"), c.params.model))
        throw UsageError("--tactor-model: unknown model '" + cl.value("--tactor-model") + "' (one of " + tactors::kModelNames + ")");
    if (cl.has("--tactor-hz")) {
        if (c.params.model == tactors::TactorModel::Erm) throw UsageError("--tactor-hz applies to lra and voice-coil (an ERM's carrier follows its level)");
        const double hz = cl.number("--tactor-hz", 0.0);
        if (!(hz >= 40.0 && hz <= 400.0)) throw UsageError("--tactor-hz must lie in 40..400");
        (c.params.model == tactors::TactorModel::Lra ? c.params.lraHz : c.params.voiceCoilHz) = hz;
    }
    if (cl.has("--tactor-sound")) {
        if (c.params.model != tactors::TactorModel::VoiceCoil) throw UsageError("--tactor-sound hands the scene's sound to a voice coil: add --tactor-model voice-coil");
        c.params.voiceCoilSound = true;
    }
    try {
        c.map = cl.has("--tactor-map") ? tactors::parseChannelMap(cl.value("--tactor-map"), motors) : tactors::ChannelMap::identity(motors);
    } catch (const core::InputError& e) {
        throw UsageError(e.what());
    }
    if (cl.has("--tactor-gain")) c.gains = tactors::loadTactorGains(cl.value("--tactor-gain"));
    if (c.gains.count > c.map.channels)
        throw core::InputError(c.gains.source, 0, "gain",
                         "the file gives " + std::to_string(c.gains.count) + " gains but the map has " + std::to_string(c.map.channels) + " channels");
    c.connect = cl.value("--tactor-connect");
    if (cl.has("--tactor-connect") && c.device != "jack") throw UsageError("--tactor-connect applies to --tactors jack");
    if (cl.has("--tactor-connect") && c.connect.empty()) throw UsageError("--tactor-connect needs a port pattern");
    if (cl.has("--tactor-rate")) {
        if (c.device == "jack") throw UsageError("--tactor-rate applies to an ALSA device (JACK runs at its server's rate)");
        c.sampleRate = cl.number("--tactor-rate", 48000.0);
        if (!(c.sampleRate >= 8000.0 && c.sampleRate <= 384000.0)) throw UsageError("--tactor-rate must lie in 8000..384000");
    }
    return c;
}

} // namespace armadillo::cli
