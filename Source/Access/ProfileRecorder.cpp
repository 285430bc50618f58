#include "Access/ProfileRecorder.h"
#include <algorithm>
#include <cctype>

namespace armadillo::access {

ProfileRecorder::ProfileRecorder(std::string path, std::string method, std::string date)
    : path_(std::move(path)), profile_(loadReaderProfile(path_)), method_(std::move(method))
{
    session_ = profile_.nextSession();
    profile_.sessions.push_back({session_, std::move(date), method_, 0.0});
    saveReaderProfile(path_, profile_);
}

void ProfileRecorder::record(const std::string& stage, const std::string& expected, const std::string& answer, bool correct, double rt, double t)
{
    auto lower = [](std::string s) {
        for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
        return s;
    };
    ReaderAnswer a;
    a.session = session_;
    a.stage = stage;
    a.method = method_;
    a.expected = lower(expected);
    a.answer = lower(answer);
    a.correct = correct;
    a.rt = rt;
    a.t = t;
    // The file as it is now: another session (the adaptive training) may have saved it since.
    ReaderProfile now = loadReaderProfile(path_);
    auto it = std::find_if(now.sessions.begin(), now.sessions.end(), [&](const ReaderSession& x) { return x.session == session_; });
    if (it == now.sessions.end()) it = now.sessions.insert(now.sessions.end(), profile_.sessions.back());
    if (t > 0.0) it->seconds = std::max(it->seconds, t);
    now.answers.push_back(std::move(a));
    saveReaderProfile(path_, now);
    ++recorded_;
}

} // namespace armadillo::access
