# Read by ctest after the discovered service tests (tests/CMakeLists.txt): tests with a higher
# COST start first when ctest runs in parallel and has no timings of its own yet.
set_tests_properties(CrashTest.KillNineAtFiftyMomentsLosesNoCommitAndReplaysByteForByte PROPERTIES COST 1000)
