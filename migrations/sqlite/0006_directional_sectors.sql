-- moorfret campaign store, SQLite backend, schema version 6: directional climates.
-- Released migrations are never edited: later changes go into new files.

UPDATE schema_info SET value = '6' WHERE key = 'schema_version';

-- The wave heading every sea state runs at (deg, from +x towards +y) and the directional
-- sector of the climate it belongs to (NULL for a campaign of one scatter table). Sea states
-- stored before this version read NULL for both: they ran at their campaign's
-- simulation.heading_deg.
ALTER TABLE sea_states ADD COLUMN heading_deg REAL;
ALTER TABLE sea_states ADD COLUMN sector TEXT;
