// The app's setup files (Save setup... / Load setup...): the state document as readable XML,
// written whole, read back to the same bytes, anything else refused with a reason.
#include "Plugin/PluginState.h"
#include <catch2/catch.hpp>

using namespace armadillo::plugin;

TEST_CASE("setup file: a state round-trips through a readable file; other files are refused", "[plugin][setup]")
{
    const auto dir = juce::File::getSpecialLocation(juce::File::tempDirectory).getChildFile("armadillo-setup-test");
    dir.deleteRecursively();
    REQUIRE(dir.createDirectory());
    // A state as the plugin writes it (docs/PLUGIN.md "State"): parameters and settings.
    juce::XmlElement root("ARMADILLO");
    root.setAttribute("version", 1);
    root.setAttribute("pluginVersion", "0.2.0");
    auto* params = root.createNewChildElement("PARAMETERS");
    auto* p = params->createNewChildElement("PARAM");
    p->setAttribute("id", "scene");
    p->setAttribute("value", 7);
    auto* settings = root.createNewChildElement("SETTINGS");
    settings->setAttribute("serialPort", "/dev/ttyACM0");
    settings->setAttribute("oscInMount", "phone-screen-up");
    settings->setAttribute("score", "polytope");
    juce::MemoryBlock state;
    juce::AudioProcessor::copyXmlToBinary(root, state);

    const auto file = dir.getChildFile("my rig.armadillo");
    REQUIRE(PluginState::writeSetupFile(state, file) == "");
    const auto text = file.loadFileAsString();
    CHECK(text.contains("serialPort=\"/dev/ttyACM0\""));   // readable, editable by hand
    CHECK(text.contains("<PARAM id=\"scene\" value=\"7\"/>"));
    juce::MemoryBlock back;
    REQUIRE(PluginState::readSetupFile(file, back) == "");
    CHECK(back == state);
    CHECK(dir.getNumberOfChildFiles(juce::File::findFiles) == 1);   // no temporary left beside it

    // Not a setup: missing, not XML, XML of something else, a state blob that is not a document.
    juce::MemoryBlock ignored;
    CHECK(PluginState::readSetupFile(dir.getChildFile("missing.armadillo"), ignored).contains("no such file"));
    const auto junk = dir.getChildFile("junk.armadillo");
    junk.replaceWithText("not xml at all <");
    CHECK(PluginState::readSetupFile(junk, ignored).contains("not an ARMadillo setup"));
    junk.replaceWithText("<SOMETHING_ELSE version=\"1\"/>");
    CHECK(PluginState::readSetupFile(junk, ignored).contains("not an ARMadillo setup"));
    const juce::MemoryBlock noise("garbage", 7);
    CHECK(PluginState::writeSetupFile(noise, dir.getChildFile("x.armadillo")).isNotEmpty());
    CHECK_FALSE(dir.getChildFile("x.armadillo").exists());
    dir.deleteRecursively();
}
