-- moorfret campaign store, SQLite backend, schema version 3: reduced and FE strand results.
-- Released migrations are never edited: later changes go into new files.

UPDATE schema_info SET value = '3' WHERE key = 'schema_version';

-- Strand results of two fidelities: `strand` jobs run the FE model, `strand_reduced` jobs its
-- calibrated reduced response. Where both ran for the same sea state, seed and hot spot, the
-- FE result is the one counted and the pair is compared in `fidelity_comparison`.
DROP VIEW lifetime_damage;
DROP VIEW sea_state_damage_inputs;
DROP VIEW lifetime_class_damage;
DROP VIEW sea_state_class_damage_inputs;

-- Rows that count, with the fidelity that produced them. (The FE rows are looked up through
-- the sea state's jobs and the rows' primary key: milliseconds on a 153-cell campaign, where a
-- join of the two result tables first took seconds.)
CREATE VIEW counted_damage_inputs AS
SELECT d.*,
       j.sea_state_id,
       CASE WHEN j.kind = 'strand_reduced' THEN 'reduced' ELSE 'fe' END AS fidelity
FROM damage_inputs d
JOIN jobs j ON j.id = d.job_id AND j.state = 'done' AND j.kind <> 'test'
WHERE j.kind <> 'strand_reduced'
   OR NOT EXISTS (
       SELECT 1 FROM jobs jf
       WHERE jf.sea_state_id = j.sea_state_id AND jf.kind = 'strand' AND jf.state = 'done'
         AND EXISTS (SELECT 1 FROM damage_inputs f
                     WHERE f.job_id = jf.id
                       AND f.hot_spot_index = d.hot_spot_index
                       AND f.seed_index = d.seed_index));

CREATE VIEW counted_class_damage_inputs AS
SELECT c.*,
       j.sea_state_id,
       CASE WHEN j.kind = 'strand_reduced' THEN 'reduced' ELSE 'fe' END AS fidelity
FROM class_damage_inputs c
JOIN jobs j ON j.id = c.job_id AND j.state = 'done' AND j.kind <> 'test'
WHERE j.kind <> 'strand_reduced'
   OR NOT EXISTS (
       SELECT 1 FROM jobs jf
       WHERE jf.sea_state_id = j.sea_state_id AND jf.kind = 'strand' AND jf.state = 'done'
         AND EXISTS (SELECT 1 FROM class_damage_inputs f
                     WHERE f.job_id = jf.id
                       AND f.hot_spot_index = c.hot_spot_index
                       AND f.seed_index = c.seed_index));

-- As in schema version 1, from the counted rows, with their fidelity ('mixed' when the seeds
-- of a sea state were run at different fidelities).
CREATE VIEW sea_state_damage_inputs AS
SELECT s.campaign_id,
       s.id AS sea_state_id,
       s.sea_state_index,
       s.hs_m,
       s.tp_s,
       s.occurrence_fraction,
       d.hot_spot_index,
       d.measure,
       COUNT(*) AS seeds,
       AVG(d.damage) AS damage_seed_mean,
       AVG(d.effective_duration_s) AS effective_duration_s,
       AVG(d.damage / d.effective_duration_s) AS damage_rate_per_s,
       CASE WHEN MIN(d.fidelity) = MAX(d.fidelity) THEN MIN(d.fidelity) ELSE 'mixed' END
           AS fidelity
FROM counted_damage_inputs d
JOIN sea_states s ON s.id = d.sea_state_id
GROUP BY s.campaign_id, s.id, s.sea_state_index, s.hs_m, s.tp_s, s.occurrence_fraction,
         d.hot_spot_index, d.measure;

CREATE VIEW lifetime_damage AS
SELECT campaign_id,
       hot_spot_index,
       measure,
       SUM(occurrence_fraction * 31557600.0 * damage_rate_per_s)
           AS annual_damage,
       SUM(occurrence_fraction) AS occurrence_covered,
       COUNT(*) AS sea_states
FROM sea_state_damage_inputs
GROUP BY campaign_id, hot_spot_index, measure;

-- As in schema version 2, from the counted rows, with their fidelity.
CREATE VIEW sea_state_class_damage_inputs AS
SELECT s.campaign_id,
       s.id AS sea_state_id,
       s.sea_state_index,
       s.hs_m,
       s.tp_s,
       s.occurrence_fraction,
       c.hot_spot_index,
       c.layer_interface,
       c.angular_position,
       m.measure,
       COUNT(*) AS seeds,
       MAX(c.contacts) AS contacts,
       AVG(c.effective_duration_s) AS effective_duration_s,
       AVG(CASE WHEN m.measure = 'fretting_max' THEN c.fretting_damage_rate_max_per_s
                ELSE c.fretting_damage_rate_mean_per_s END) AS damage_rate_per_s,
       AVG(c.effective_duration_s * CASE WHEN m.measure = 'fretting_max'
                THEN c.fretting_damage_rate_max_per_s
                ELSE c.fretting_damage_rate_mean_per_s END) AS damage_seed_mean,
       AVG(c.stick_cycles_per_hour) AS stick_cycles_per_hour,
       AVG(c.partial_slip_cycles_per_hour) AS partial_slip_cycles_per_hour,
       AVG(c.gross_slip_cycles_per_hour) AS gross_slip_cycles_per_hour,
       MAX(c.ruiz_f1_max) AS ruiz_f1_max,
       MAX(c.ruiz_f2_max) AS ruiz_f2_max,
       MAX(c.peak_pressure_max_pa) AS peak_pressure_max_pa,
       MAX(c.slip_amplitude_max_m) AS slip_amplitude_max_m,
       CASE WHEN MIN(c.fidelity) = MAX(c.fidelity) THEN MIN(c.fidelity) ELSE 'mixed' END
           AS fidelity
FROM counted_class_damage_inputs c
JOIN sea_states s ON s.id = c.sea_state_id
CROSS JOIN (SELECT 'fretting_max' AS measure UNION ALL SELECT 'fretting_mean' AS measure) m
GROUP BY s.campaign_id, s.id, s.sea_state_index, s.hs_m, s.tp_s, s.occurrence_fraction,
         c.hot_spot_index, c.layer_interface, c.angular_position, m.measure;

CREATE VIEW lifetime_class_damage AS
SELECT campaign_id,
       hot_spot_index,
       layer_interface,
       angular_position,
       measure,
       SUM(occurrence_fraction * 31557600.0 * damage_rate_per_s) AS annual_damage,
       SUM(occurrence_fraction) AS occurrence_covered,
       COUNT(*) AS sea_states
FROM sea_state_class_damage_inputs
GROUP BY campaign_id, hot_spot_index, layer_interface, angular_position, measure;

-- Reduced against FE where both ran: per sea state, seed, hot spot and contact class.
CREATE VIEW fidelity_comparison AS
SELECT s.campaign_id,
       s.sea_state_index,
       s.hs_m,
       s.tp_s,
       s.occurrence_fraction,
       f.seed_index,
       f.hot_spot_index,
       f.layer_interface,
       f.angular_position,
       r.fretting_damage_rate_max_per_s AS reduced_damage_rate_max_per_s,
       f.fretting_damage_rate_max_per_s AS fe_damage_rate_max_per_s,
       r.fretting_damage_rate_mean_per_s AS reduced_damage_rate_mean_per_s,
       f.fretting_damage_rate_mean_per_s AS fe_damage_rate_mean_per_s,
       r.slip_amplitude_max_m AS reduced_slip_amplitude_max_m,
       f.slip_amplitude_max_m AS fe_slip_amplitude_max_m,
       r.partial_slip_cycles_per_hour + r.gross_slip_cycles_per_hour
           AS reduced_slip_cycles_per_hour,
       f.partial_slip_cycles_per_hour + f.gross_slip_cycles_per_hour
           AS fe_slip_cycles_per_hour
FROM class_damage_inputs f
JOIN jobs jf ON jf.id = f.job_id AND jf.state = 'done' AND jf.kind = 'strand'
JOIN jobs jr ON jr.sea_state_id = jf.sea_state_id AND jr.state = 'done'
    AND jr.kind = 'strand_reduced'
JOIN class_damage_inputs r ON r.job_id = jr.id
    AND r.seed_index = f.seed_index
    AND r.hot_spot_index = f.hot_spot_index
    AND r.layer_interface = f.layer_interface
    AND r.angular_position = f.angular_position
JOIN sea_states s ON s.id = jf.sea_state_id;
