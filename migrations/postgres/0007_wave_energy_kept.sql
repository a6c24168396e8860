-- moorfret campaign store, PostgreSQL backend, schema version 7: the wave energy every sea state
-- keeps.
-- Released migrations are never edited: later changes go into new files.

UPDATE schema_info SET value = '7' WHERE key = 'schema_version';

-- The fraction of the sea state's JONSWAP variance m0 at or below the global stage's wave
-- cut-off (moorfret_campaign::sea_limits), computed at planning: the loads of the rest of the
-- sea are not computed. Below 0.9 the sea state is flagged (named at launch, marked in
-- queries and the report). Sea states stored before this version read NULL.
ALTER TABLE sea_states ADD COLUMN wave_energy_kept DOUBLE PRECISION;
