# The *_test.py scripts here are rostest nodes (run by their .test files
# through test/integration/test_rostest_files.py), not pytest modules.
collect_ignore_glob = ['*_test.py']
