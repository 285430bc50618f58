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
    profile_.answers.push_back(std::move(a));
    if (t > 0.0) profile_.sessions.back().seconds = std::max(profile_.sessions.back().seconds, t);
    ++recorded_;
    saveReaderProfile(path_, profile_);
}

} // namespace armadillo::access
