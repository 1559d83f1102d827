namespace ssvgi {}
