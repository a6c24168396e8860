//! fretting (module under construction).
