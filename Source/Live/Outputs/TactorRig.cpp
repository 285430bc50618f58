#include "Live/Outputs/TactorRig.h"
#include "Core/Text.h"
#include "Core/Errors.h"
#include "Live/Outputs/TactorOutput.h"
#include <cmath>
#include <sstream>

namespace armadillo::live {

TactorRig::TactorRig(BlockControl& control, ControlToken& token) : control_(control), token_(token) {}

TactorRig::~TactorRig()
{
    closeOutput();
}

std::unique_ptr<tactors::TactorRenderer> TactorRig::build(const TactorSettings& settings, int channels, int motors,
                                                          double sampleRate, std::string& why)
{
    try {
        const auto setup = tactors::resolveTactorSetup(settings.model, settings.map, settings.gains, motors, channels);
        auto params = setup.params;
        params.voiceCoilSound = settings.sound && params.model == tactors::TactorModel::VoiceCoil;
        auto renderer = std::make_unique<tactors::TactorRenderer>();
        renderer->prepare(params, setup.map, setup.gains, sampleRate);
        return renderer;
    } catch (const std::exception& e) {
        why = std::string("Tactors: ") + e.what();
        return nullptr;
    }
}

std::string TactorRig::prepareBus(const TactorSettings& settings, int busChannels, int motors, double sampleRate)
{
    busChannels_ = busChannels;
    sampleRate_ = sampleRate;
    waiting_.reset();
    std::string why;
    std::unique_ptr<tactors::TactorRenderer> renderer;
    if (busChannels > 0) renderer = build(settings, busChannels, motors, sampleRate, why);
    busMap_ = renderer != nullptr ? renderer->map() : tactors::ChannelMap {};
    control_.installTactors(std::move(renderer));
    return !why.empty() ? why + " (the Tactors bus stays silent)" : why;
}

std::string TactorRig::settingsChanged(const TactorSettings& settings, int motors)
{
    std::string why;
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
        if (const auto failed = openOutput(settings, motors); !failed.empty()) why = why.empty() ? failed : why + "; " + failed;
    return why;
}

void TactorRig::tick()
{
    control_.collectTactors();
    if (waiting_ != nullptr) control_.offerTactors(waiting_);   // refused while one is in flight: the next tick
}

std::string TactorRig::openOutput(const TactorSettings& settings, int motors)
{
    closeOutput();
    const std::string device = core::trimmed(settings.device);
    if (device.empty()) return "Tactors: choose an output (jack, or an ALSA device such as hw:1)";
    try {
        const auto setup = tactors::resolveTactorSetup(settings.model, settings.map, settings.gains, motors, 0);
        live::TactorOutputConfig config;
        config.device = device;
        config.params = setup.params;
        config.params.voiceCoilSound = settings.sound && config.params.model == tactors::TactorModel::VoiceCoil;
        config.map = setup.map;
        config.gains = setup.gains;
        config.connect = core::trimmed(settings.connect);
        config.clientName = "ARMadillo";
        auto output = std::make_unique<TactorOutput>(config);   // IoError / InputError: nothing opened
        if (output->wantsSound() && std::abs(output->sampleRate() - sampleRate_) > 0.5) {
            std::ostringstream why;
            why << "Tactors: the voice coil takes the scene's sound sample for sample, but the tactor output runs at " << output->sampleRate()
                << " Hz and the sound at " << sampleRate_ << " Hz";
            return why.str();
        }
        output->start();
        output_ = std::move(output);
        control_.setTactorOutput(output_.get());
        return {};
    } catch (const std::exception& e) {
        return std::string("Tactors: ") + e.what();
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

std::string TactorRig::outputStatus() const
{
    if (output_ == nullptr) return "off";
    if (output_->failed()) return "stopped: the JACK server or sound card went away";
    return output_->describe();
}

int TactorRig::motorOfChannel(int channel, const TactorSettings& settings, int motors) const
{
    tactors::ChannelMap map = output_ != nullptr ? output_->map() : busMap_;
    if (map.channels == 0) {   // neither open: the map the settings name
        try {
            map = tactors::resolveTactorSetup("erm", settings.map, {}, motors, 0).map;
        } catch (const std::exception&) {
            return -1;
        }
    }
    return channel >= 0 && channel < map.channels ? map.motor[static_cast<std::size_t>(channel)] : -1;
}

} // namespace armadillo::live
