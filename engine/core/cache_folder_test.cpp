// core/cache_folder.h: the variable, then XDG_CACHE_HOME, then HOME.
#include "core/cache_folder.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <optional>
#include <string>

using namespace metamer;

namespace {

// Sets an environment variable for the scope, restoring it after.
class ScopedEnv {
public:
    ScopedEnv(const char* name, const char* value) : name_(name) {
        if (const char* old = std::getenv(name)) old_ = old;
        value ? setenv(name, value, 1) : unsetenv(name);
    }
    ~ScopedEnv() { old_ ? setenv(name_, old_->c_str(), 1) : unsetenv(name_); }

private:
    const char* name_;
    std::optional<std::string> old_;
};

}  // namespace

TEST(CacheFolder, VariableThenXdgThenHome) {
    ScopedEnv home("HOME", "/home/someone"), xdg("XDG_CACHE_HOME", nullptr), own("METAMER_TEST_CACHE", nullptr);
    EXPECT_EQ(cacheFolder("METAMER_TEST_CACHE"), "/home/someone/.cache/metamer");
    {
        ScopedEnv x("XDG_CACHE_HOME", "/var/cache/x");
        EXPECT_EQ(cacheFolder("METAMER_TEST_CACHE"), "/var/cache/x/metamer");
        ScopedEnv v("METAMER_TEST_CACHE", "/tmp/here");
        EXPECT_EQ(cacheFolder("METAMER_TEST_CACHE"), "/tmp/here");
    }
    ScopedEnv off("METAMER_TEST_CACHE", "off");
    EXPECT_TRUE(cacheFolder("METAMER_TEST_CACHE").empty());
}
