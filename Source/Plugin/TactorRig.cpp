#include "Plugin/TactorRig.h"
#include "Core/Errors.h"
#include "Live/TactorOutput.h"
#include "Plugin/PluginState.h"
#include <cmath>

namespace armadillo::plugin {

TactorRig::TactorRig(live::BlockControl& control, live::ControlToken& token) : control_(control), token_(token) {}

TactorRig::~TactorRig()
{
    closeOutput();
}

std::unique_ptr<tactors::TactorRenderer> TactorRig::build(const juce::ValueTree& settings, int channels, int motors,
                                                          double sampleRate, juce::String& why)
{
    try {
        const auto setup = tactors::resolveTactorSetup(settings[SettingIds::tactorModel].toString().toStdString(),
                                                       settings[SettingIds::tactorMap].toString().toStdString(),
                                                       settings[SettingIds::tactorGains].toString().toStdString(), motors, channels);
        auto params = setup.params;
        params.voiceCoilSound = static_cast<bool>(settings[SettingIds::tactorSound]) && params.model == tactors::TactorModel::VoiceCoil;
        auto renderer = std::make_unique<tactors::TactorRenderer>();
        renderer->prepare(params, setup.map, setup.gains, sampleRate);
        return renderer;
    } catch (const std::exception& e) {
        why = "Tactors: " + juce::String(e.what());
        return nullptr;
    }
}

juce::String TactorRig::prepareBus(const juce::ValueTree& settings, int busChannels, int motors, double sampleRate)
{
    busChannels_ = busChannels;
    sampleRate_ = sampleRate;
    waiting_.reset();
    juce::String why;
    std::unique_ptr<tactors::TactorRenderer> renderer;
    if (busChannels > 0) renderer = build(settings, busChannels, motors, sampleRate, why);
    busMap_ = renderer != nullptr ? renderer->map() : tactors::ChannelMap {};
    control_.installTactors(std::move(renderer));
    return why.isNotEmpty() ? why + " (the Tactors bus stays silent)" : why;
}

juce::String TactorRig::settingsChanged(const juce::ValueTree& settings, int motors)
{
    juce::String why;
    if (busChannels_ > 0) {
        auto renderer = build(settings, busChannels_, motors, sampleRate_, why);
        if (renderer == nullptr) {   // silent rather than half-right: a renderer whose channels play nothing
            renderer = std::make_unique<tactors::TactorRenderer>();
            tactors::ChannelMap silent;
            silent.channels = busChannels_;
            silent.motor.fill(-1);
            renderer->prepare(tactors::kDefaultTactorParams, silent, tactors::TactorGains {}, sampleRate_);
            why += " (the Tactors bus stays silent)";
        }
        busMap_ = renderer->map();
        waiting_ = std::move(renderer);
        tick();
    }
    if (output_ != nullptr)
        if (const auto failed = openOutput(settings, motors); failed.isNotEmpty()) why = why.isEmpty() ? failed : why + "; " + failed;
    return why;
}

void TactorRig::tick()
{
    control_.collectTactors();
    if (waiting_ != nullptr) control_.offerTactors(waiting_);   // refused while one is in flight: the next tick
}

juce::String TactorRig::openOutput(const juce::ValueTree& settings, int motors)
{
    closeOutput();
    const auto device = settings[SettingIds::tactorDevice].toString().trim();
    if (device.isEmpty()) return "Tactors: choose an output (jack, or an ALSA device such as hw:1)";
    try {
        const auto setup = tactors::resolveTactorSetup(settings[SettingIds::tactorModel].toString().toStdString(),
                                                       settings[SettingIds::tactorMap].toString().toStdString(),
                                                       settings[SettingIds::tactorGains].toString().toStdString(), motors, 0);
        live::TactorOutputConfig config;
        config.device = device.toStdString();
        config.params = setup.params;
        config.params.voiceCoilSound = static_cast<bool>(settings[SettingIds::tactorSound]) && config.params.model == tactors::TactorModel::VoiceCoil;
        config.map = setup.map;
        config.gains = setup.gains;
        config.connect = settings[SettingIds::tactorConnect].toString().trim().toStdString();
        config.clientName = "ARMadillo";
        auto output = std::make_unique<live::TactorOutput>(config);   // IoError / InputError: nothing opened
        if (output->wantsSound() && std::abs(output->sampleRate() - sampleRate_) > 0.5)
            return "Tactors: the voice coil takes the scene's sound sample for sample, but the tactor output runs at "
                   + juce::String(output->sampleRate()) + " Hz and the sound at " + juce::String(sampleRate_) + " Hz";
        output->start();
        output_ = std::move(output);
        control_.setTactorOutput(output_.get());
        return {};
    } catch (const std::exception& e) {
        return "Tactors: " + juce::String(e.what());
    }
}

void TactorRig::closeOutput()
{
    if (output_ == nullptr) return;
    control_.setTactorOutput(nullptr);
    token_.take();   // a control step that loaded the pointer before it was cleared has finished
    token_.release();
    output_->stop();
    output_.reset();
}

juce::String TactorRig::outputStatus() const
{
    if (output_ == nullptr) return "off";
    if (output_->failed()) return "stopped: the JACK server or sound card went away";
    return juce::String(output_->describe());
}

int TactorRig::motorOfChannel(int channel, const juce::ValueTree& settings, int motors) const
{
    tactors::ChannelMap map = output_ != nullptr ? output_->map() : busMap_;
    if (map.channels == 0) {   // neither open: the map the settings name
        try {
            map = tactors::resolveTactorSetup("erm", settings[SettingIds::tactorMap].toString().toStdString(), {}, motors, 0).map;
        } catch (const std::exception&) {
            return -1;
        }
    }
    return channel >= 0 && channel < map.channels ? map.motor[static_cast<std::size_t>(channel)] : -1;
}

} // namespace armadillo::plugin
