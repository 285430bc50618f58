#include "Mqtt/ArmMessages.h"
#include "Core/Errors.h"
#include <cctype>

namespace armadillo::mqtt {

namespace {

std::string lowerAscii(std::string s)
{
    for (char& c : s)
        if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
    return s;
}

} // namespace

std::string applyShorthand(const std::string& text, const std::vector<std::pair<std::string, std::string>>& shorthand)
{
    if (shorthand.empty()) return text;
    std::string out;
    std::size_t i = 0;
    while (i <= text.size()) {
        const std::size_t sp = text.find(' ', i);
        const std::string word = text.substr(i, sp == std::string::npos ? std::string::npos : sp - i);
        std::string shown = word;
        const std::string key = lowerAscii(word);
        for (const auto& [shortForm, full] : shorthand)
            if (lowerAscii(full) == key) {
                shown = shortForm;
                break;
            }
        out += shown;
        if (sp == std::string::npos) break;
        out += ' ';
        i = sp + 1;
    }
    return out;
}

MessagePresenter::MessagePresenter(MessageInbox& inbox, PresenterOptions options) : inbox_(inbox), options_(std::move(options)) {}

bool MessagePresenter::handOver(braille::BrailleSceneControls& scene, const InboxMessage& m, std::vector<std::string>& said)
{
    std::unique_ptr<braille::ArmMessage> prepared;
    const std::string text = applyShorthand(m.text, options_.shorthand);
    try {
        prepared = braille::prepareArmMessage(text, "message " + std::to_string(m.id) + " from '" + m.source + "'", options_.grade,
                                              options_.method, options_.timed, m.urgent, m.id);
    } catch (const core::InputError& e) {
        ++unshowable_;
        said.push_back(std::string("not shown: ") + e.what());
        return false;
    }
    if (!scene.showMessage(prepared.get())) {
        said.push_back("message " + std::to_string(m.id) + " not shown: the scene has 4 messages waiting");
        ++unshowable_;
        return false;
    }
    said.push_back("message " + std::to_string(m.id) + " from '" + m.source + "'" + (m.urgent ? " (urgent)" : "") + " on the arm: " + text);
    handed_.emplace(m.id, Handed {std::move(prepared), m});
    return true;
}

std::vector<std::string> MessagePresenter::poll(braille::BrailleSceneControls& scene)
{
    std::vector<std::string> said;
    std::uint64_t id = 0;
    bool interrupted = false;
    while (scene.takeFinishedMessage(id, interrupted)) {
        const auto it = handed_.find(id);
        if (it == handed_.end()) continue;
        if (interrupted && !it->second.message.urgent) {
            said.push_back("message " + std::to_string(id) + " interrupted: shown again next");
            again_.push_front(it->second.message);
        } else {
            ++shown_;
            said.push_back("message " + std::to_string(id) + (interrupted ? " interrupted by a more urgent one" : " shown"));
        }
        handed_.erase(it);
    }
    InboxMessage m;
    // Urgent ones at once (the scene interrupts); the others when the scene is free.
    while (inbox_.urgentWaiting() && inbox_.pop(m)) handOver(scene, m, said);
    if (!scene.messageBusy()) {
        if (!again_.empty()) {
            m = again_.front();
            again_.pop_front();
            handOver(scene, m, said);
        } else if (inbox_.pop(m)) {
            handOver(scene, m, said);
        }
    }
    return said;
}

} // namespace armadillo::mqtt
