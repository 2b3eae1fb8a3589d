# Read by ctest after the discovered service tests (tests/CMakeLists.txt): tests with a higher
# COST start first when ctest runs in parallel and has no timings of its own yet.
set_tests_properties(CrashTest.KillNineAtFiftyMomentsLosesNoCommitAndReplaysByteForByte PROPERTIES COST 1000)
# Eight viewers looping on two 100,000-sample roadmaps load both cores: it runs alone. The plain
# partition test's long-lived replica fell behind in 3 runs of 3 that ran beside or after it
# (never caught up within 60 s in round 1), and passed in 3 runs of 3 alone and in two full runs:
# not understood (see docs/results/fleet.md). The partition and stall campaigns, long, start early.
set_tests_properties(ServiceTest.LoopingViewersNeverHoldUpAnUnloadADropOrTheStop PROPERTIES RUN_SERIAL TRUE)
# Four browsers on the gateway run alone too: in 2 of 4 full parallel runs (2026-11-26 and -27)
# a new page's load timed out at 30 s (once explained: a daemon re-announcing every 5 s, since
# removed; once not), while it passed 6 runs of 6 alone or beside the partition, stall and crash
# tests. Not understood; see docs/results/service.md.
set_tests_properties(WebViewerTest.FourBrowsersFollowABuildAndDrawWhatStatsSays PROPERTIES RUN_SERIAL TRUE)
set_tests_properties(PartitionTest.CutAndHealTheOwnerPlain PartitionTest.CutAndHealTheOwnerSecured
                     HistoryTest.RandomFaultsLoseNoAcknowledgedChange
                     StallTest.AnOwnerStalledPastItsLeaseRejoinsAndTheFleetSettlesOnOneOwner PROPERTIES COST 500)
# The secured stall campaign runs alone. On 2026-11-27 it and the secured partition campaign each
# failed once in a full parallel run, beside the kill -9 campaign, and passed alone (88 s, 89 s).
# The partition failure was a product race, since fixed: a secured daemon that rejoined (a new
# participant) deleted its old participant first, and a peer that had not authenticated the new
# one yet read the leave as "left while holding scene" and took the scene over
# (RejoinTest.ASecuredDaemonThatRejoinsKeepsItsScenes). The stall failure's output was lost; it
# may have been the same race or the domain cross-talk fixed the same day (local_daemon.cpp).
set_tests_properties(StallTest.AnOwnerStalledPastItsLeaseRejoinsAndTheFleetSettlesOnOneOwner PROPERTIES RUN_SERIAL TRUE)
# The client of another vendor (tests/vendor/, Cyclone DDS): `ctest -L vendor` runs it alone. Its
# hundred fresh clients take about 80 s in a row and start early.
set_tests_properties(VendorTest.ACycloneClientReadsStatusUpdatesStatsAndATourWithProgress
                     VendorTest.AHundredFreshCycloneClientsLoseNoFirstReply PROPERTIES LABELS "service;vendor")
set_tests_properties(VendorTest.AHundredFreshCycloneClientsLoseNoFirstReply PROPERTIES COST 300)
# A page of another origin in headless Chromium (one page, a few seconds) runs alone too, like
# the four browsers above: a page's load is what timed out beside the rest.
set_tests_properties(WebGatewayTest.APageOfAnotherOriginCannotOpenTheWebSocket PROPERTIES RUN_SERIAL TRUE)
# So does the page behind nginx (one page and a 20,000-sample build, about 11 s).
set_tests_properties(WebProxyTest.ChromiumFollowsABuildOverHttpsAndWssAndTheBoundsHoldThroughTheProxy PROPERTIES RUN_SERIAL TRUE)
