#!/usr/bin/env python3
"""Removes one fsync of the store at a time, rebuilds the server unit tests, and runs the power-cut
campaign (PowerCutTest.*) against it: which removals the campaign catches. Run from the repository
root after deploy/build.sh release; every source file is put back as it was, and the tests rebuilt.
Usage: python3 tests/tools/fsync_ablation.py [LETTERS]   (e.g. A C: only those cases)"""
import subprocess, sys, shutil
cases = [
 ("A journal append fsync (RecordFileWriter::append)", "common/roadmap/src/record_file.cpp", "    write_pieces(*file_, payload, path_, {});\n    file_->sync();", "    write_pieces(*file_, payload, path_, {});"),
 ("B temporary file fsync before rename (replace_atomically)", "common/roadmap/src/record_file.cpp", "      write(*file, tmp);\n      file->sync();", "      write(*file, tmp);"),
 ("C directory fsync after rename (replace_atomically)", "common/roadmap/src/record_file.cpp", "    throw;\n  }\n  fsync_directory_of(path, fs);\n}", "    throw;\n  }\n}"),
 ("D new journal's fsync (RecordFileWriter constructor)", "common/roadmap/src/record_file.cpp", "  file_->sync();\n  fsync_directory_of(path_, fs);\n}", "  fsync_directory_of(path_, fs);\n}"),
 ("E new journal's directory fsync (RecordFileWriter constructor)", "common/roadmap/src/record_file.cpp", "  file_->sync();\n  fsync_directory_of(path_, fs);\n}", "  file_->sync();\n}"),
 ("F data directory fsync after a new store's rename (RoadmapStore::create)", "server/service/src/roadmap_store.cpp", "    fs.rename(staging, dir);\n    fsync_directory_of(dir, fs);", "    fs.rename(staging, dir);"),
 ("G data directory fsync after a replacing store's exchange (take_place)", "server/service/src/roadmap_store.cpp", "  fsync_directory_of(replaces_, fs_);\n  fs_.remove_all(staging);", "  fs_.remove_all(staging);"),
 ("H store directory fsync after rotating the journal (start_compaction)", "server/service/src/roadmap_store_compaction.cpp", "      fs_.rename(journal_path(dir_), old_journal_path(dir_));\n      fsync_directory_of(journal_path(dir_), fs_);", "      fs_.rename(journal_path(dir_), old_journal_path(dir_));"),
 ("I store directory fsync after removing journal.old (fold)", "server/service/src/roadmap_store_compaction.cpp", "      fs_.remove(old_journal_path(dir));\n      fsync_directory_of(old_journal_path(dir), fs_);", "      fs_.remove(old_journal_path(dir));"),
 ("J data directory fsync in drop_store", "server/service/src/roadmap_store.cpp", "  fs.rename(dir, aside);\n  fsync_directory_of(dir, fs);", "  fs.rename(dir, aside);"),
]
sel = sys.argv[1:] 
for name, path, old, new in cases:
    if sel and name[0] not in sel: continue
    src = open(path).read()
    assert src.count(old) == 1, (name, src.count(old))
    shutil.copy(path, "/tmp/ablation.bak")
    open(path, "w").write(src.replace(old, new))
    try:
        b = subprocess.run("cd build && ninja ispars_server_unit_tests", shell=True, capture_output=True, text=True)
        if b.returncode != 0:
            print(name, ": BUILD FAILED", b.stdout[-2000:])
            continue
        r = subprocess.run("cd build && ./bin/ispars_server_unit_tests --gtest_filter=PowerCutTest*", shell=True, capture_output=True, text=True)
        fails = r.stdout.count("Failure")
        first = ""
        for line in r.stdout.splitlines():
            if "power cut at operation" in line: first = line.split("test_roadmap_store_power_cut.cpp:")[-1]; break
        msg = ""
        lines = r.stdout.splitlines()
        for i,l in enumerate(lines):
            if "Failure" in l:
                msg = " | ".join(lines[i+1:i+4]); break
        print(f"{name}: {'DETECTED' if r.returncode else 'not detected'} ({fails} failures; first: {first.strip()} : {msg[:200]})", flush=True)
    finally:
        shutil.copy("/tmp/ablation.bak", path)
subprocess.run("cd build && ninja ispars_server_unit_tests", shell=True, capture_output=True)
