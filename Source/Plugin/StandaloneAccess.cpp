#include "Plugin/StandaloneAccess.h"
#include <juce_audio_devices/juce_audio_devices.h>
#include <juce_audio_utils/juce_audio_utils.h>
#include <juce_gui_extra/juce_gui_extra.h>
#if JucePlugin_Build_Standalone
// JUCE 7.0.5's standalone wrapper (the header its Standalone target compiles, included here for
// StandalonePluginHolder::getInstance(), getMuteInputValue() and showAudioSettingsDialog()).
#include <juce_audio_plugin_client/Standalone/juce_StandaloneFilterWindow.h>
#endif

namespace armadillo::plugin {

#if JucePlugin_Build_Standalone
namespace {
juce::StandalonePluginHolder* holder()
{
    return juce::StandalonePluginHolder::getInstance();
}
} // namespace

StandaloneAudio standaloneAudio()
{
    StandaloneAudio a;
    auto* h = holder();
    if (h == nullptr) return a;
    a.standalone = true;
    a.inputMuted = static_cast<bool>(h->getMuteInputValue().getValue()) ? 1 : 0;
    if (auto* device = h->deviceManager.getCurrentAudioDevice()) {
        a.deviceOpen = true;
        a.deviceType = device->getTypeName();
        juce::AudioDeviceManager::AudioDeviceSetup setup;
        h->deviceManager.getAudioDeviceSetup(setup);
        a.output = setup.outputDeviceName;
        a.input = setup.inputDeviceName;
        a.inputChannels = device->getActiveInputChannels().countNumberOfSetBits();
        a.sampleRate = device->getCurrentSampleRate();
    }
    return a;
}

bool setStandaloneInputMuted(bool muted)
{
    auto* h = holder();
    if (h == nullptr) return false;
    h->getMuteInputValue().setValue(muted);   // the wrapper's own Value: its banner and settings follow
    return true;
}

bool showStandaloneAudioSettings()
{
    auto* h = holder();
    if (h == nullptr) return false;
    h->showAudioSettingsDialog();
    return true;
}
#else
StandaloneAudio standaloneAudio() { return {}; }
bool setStandaloneInputMuted(bool) { return false; }
bool showStandaloneAudioSettings() { return false; }
#endif

} // namespace armadillo::plugin
