#pragma once
// Adds the answers of a training that is not the adaptive one (the §4.4.1 protocol in the app's
// Training panel) to a reader profile (ReaderProfile.h), as one new session: the progress report
// and the next adaptive plan then count them too. The profile is saved (atomically) after every
// answer, so nothing is lost when the app stops. Not real-time: one owner thread (the app's
// message thread).
#include "Access/ReaderProfile.h"
#include <string>

namespace armadillo::access {

class ProfileRecorder {
public:
    /// Loads the profile at `path` (a file not there yet: a new reader) and saves it at once with
    /// the new session, so an unreadable or unwritable file is refused now (InputError, IoError).
    ProfileRecorder(std::string path, std::string method, std::string date);
    /// One answer (stage, expected and answer as the training logs them; rt and t in s, < 0 =
    /// unknown; t also extends the session's length), added to the file as it is now (another
    /// session may have saved it meanwhile). Saves; InputError / IoError when it cannot.
    void record(const std::string& stage, const std::string& expected, const std::string& answer, bool correct, double rt, double t);
    int session() const noexcept { return session_; }
    const std::string& path() const noexcept { return path_; }
    int recorded() const noexcept { return recorded_; }

private:
    std::string path_;
    ReaderProfile profile_;
    int session_ = 1, recorded_ = 0;
    std::string method_;
};

} // namespace armadillo::access
