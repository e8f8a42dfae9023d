// Fixture of ctest format.CheckCatchesAMisformattedFile: scripts/check-format.sh must reject it.
int  misformatted( ){return 1;}
