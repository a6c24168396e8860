-- moorfret campaign store, PostgreSQL backend, schema version 5: the contact-stress fretting law.
-- Released migrations are never edited: later changes go into new files.

UPDATE schema_info SET value = '5' WHERE key = 'schema_version';

-- Beside the campaign's fretting law (the `fretting_*` columns, by default the contact-stress
-- law), every class row carries the rope S-N law charged per slip cycle (`rope_tn_*`, the law of
-- schema versions 1-4) and the largest gross-slip frictional power of a contact of the class.
-- Rows written before this version read 0 there.
ALTER TABLE class_damage_inputs ADD COLUMN rope_tn_damage_rate_max_per_s DOUBLE PRECISION NOT NULL DEFAULT 0;
ALTER TABLE class_damage_inputs ADD COLUMN rope_tn_damage_rate_mean_per_s DOUBLE PRECISION NOT NULL DEFAULT 0;
ALTER TABLE class_damage_inputs ADD COLUMN wear_power_max_w DOUBLE PRECISION NOT NULL DEFAULT 0;

-- The class views of schema version 4 with the measures `rope_tn_max` and `rope_tn_mean`
-- beside `fretting_max` and `fretting_mean`, and the mean over seeds of the largest wear power.
DROP VIEW lifetime_class_damage;
DROP VIEW sea_state_class_damage_inputs;
DROP VIEW counted_class_damage_inputs;

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

CREATE VIEW sea_state_class_damage_inputs AS
WITH r AS (
    SELECT c.*, m.measure,
           CASE m.measure
                WHEN 'fretting_max' THEN c.fretting_damage_rate_max_per_s
                WHEN 'fretting_mean' THEN c.fretting_damage_rate_mean_per_s
                WHEN 'rope_tn_max' THEN c.rope_tn_damage_rate_max_per_s
                ELSE c.rope_tn_damage_rate_mean_per_s END AS rate
    FROM counted_class_damage_inputs c
    CROSS JOIN (SELECT 'fretting_max' AS measure UNION ALL SELECT 'fretting_mean' AS measure
                UNION ALL SELECT 'rope_tn_max' AS measure
                UNION ALL SELECT 'rope_tn_mean' AS measure) m
), g AS (
    SELECT sea_state_id, hot_spot_index, layer_interface, angular_position, measure,
           AVG(rate) AS mean_rate
    FROM r GROUP BY sea_state_id, hot_spot_index, layer_interface, angular_position, measure
)
SELECT s.campaign_id,
       s.id AS sea_state_id,
       s.sea_state_index,
       s.hs_m,
       s.tp_s,
       s.occurrence_fraction,
       r.hot_spot_index,
       r.layer_interface,
       r.angular_position,
       r.measure,
       COUNT(*) AS seeds,
       MAX(r.contacts) AS contacts,
       AVG(r.effective_duration_s) AS effective_duration_s,
       AVG(r.rate) AS damage_rate_per_s,
       AVG(r.effective_duration_s * r.rate) AS damage_seed_mean,
       CASE WHEN COUNT(*) > 1
            THEN SUM((r.rate - g.mean_rate) * (r.rate - g.mean_rate)) / (COUNT(*) - 1)
       END AS damage_rate_variance,
       AVG(r.stick_cycles_per_hour) AS stick_cycles_per_hour,
       AVG(r.partial_slip_cycles_per_hour) AS partial_slip_cycles_per_hour,
       AVG(r.gross_slip_cycles_per_hour) AS gross_slip_cycles_per_hour,
       MAX(r.ruiz_f1_max) AS ruiz_f1_max,
       MAX(r.ruiz_f2_max) AS ruiz_f2_max,
       MAX(r.peak_pressure_max_pa) AS peak_pressure_max_pa,
       MAX(r.slip_amplitude_max_m) AS slip_amplitude_max_m,
       AVG(r.wear_power_max_w) AS wear_power_max_w,
       CASE WHEN MIN(r.fidelity) = MAX(r.fidelity) THEN MIN(r.fidelity) ELSE 'mixed' END
           AS fidelity
FROM r
JOIN g ON g.sea_state_id = r.sea_state_id AND g.hot_spot_index = r.hot_spot_index
      AND g.layer_interface = r.layer_interface AND g.angular_position = r.angular_position
      AND g.measure = r.measure
JOIN sea_states s ON s.id = r.sea_state_id
GROUP BY s.campaign_id, s.id, s.sea_state_index, s.hs_m, s.tp_s, s.occurrence_fraction,
         r.hot_spot_index, r.layer_interface, r.angular_position, r.measure;

CREATE VIEW lifetime_class_damage AS
SELECT campaign_id,
       hot_spot_index,
       layer_interface,
       angular_position,
       measure,
       SUM(occurrence_fraction * 31557600.0 * damage_rate_per_s) AS annual_damage,
       SUM(occurrence_fraction) AS occurrence_covered,
       COUNT(*) AS sea_states,
       SUM(CASE WHEN seeds > 1
                THEN (occurrence_fraction * 31557600.0) * (occurrence_fraction * 31557600.0)
                     * damage_rate_variance / seeds
                ELSE 0.0 END) AS annual_damage_variance,
       SUM(CASE WHEN seeds > 1
                THEN (occurrence_fraction * 31557600.0) * (occurrence_fraction * 31557600.0)
                     * damage_rate_variance / seeds
                     * (occurrence_fraction * 31557600.0) * (occurrence_fraction * 31557600.0)
                     * damage_rate_variance / seeds / (seeds - 1)
                ELSE 0.0 END) AS annual_damage_variance_dof_sum,
       SUM(CASE WHEN seeds > 1 THEN 1 ELSE 0 END) AS sea_states_with_spread,
       SUM(CASE WHEN seeds > 1 THEN 0 ELSE 1 END) AS sea_states_without_spread
FROM sea_state_class_damage_inputs
GROUP BY campaign_id, hot_spot_index, layer_interface, angular_position, measure;
